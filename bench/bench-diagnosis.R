# Benchmark: does explain_discrepancy() name the cause on problems it was
# not tuned on? Written apart from the test suite's synthetic problems
# (tests/testthat/helper-synthetic.R), with simulators of different forms:
#   embedded   the package's monthly model (ISO 13790), equipment power
#              density and infiltration calibrated;
#   degreeday  a model written here: base load plus heating and cooling by
#              degree-days with a soft balance point, solar gains through the
#              cooling plant; heat loss coefficient and base load calibrated.
# Each problem: 48 months of weather (2012, 2013 and a perturbed copy of
# both), true parameters drawn in the middle 60 % of their ranges, a hidden
# effect of one shape, noise sd 15 kWh; 30 runs (one Latin hypercube per
# simulator); 36 months fitted (2 chains x 600 at adapt_delta 0.9), 12 held
# out. Shapes and the names that count as right:
#   none            no effect (a false alarm is any cause named)
#   covariate       250 kWh x occupancy                  "occupancy"
#   step            200 kWh from month 15 on             "after_change"
#   region          250 kWh where rh > 47                "rh > ..."
#   interaction     8 kWh per % rh, where temp > 15      "rh, where temp > ..."
#   multiplicative  10 % of the simulator's output       (no candidate names it)
# The candidates: the inputs, occupancy, after_change and a decoy that
# follows temperature. When the right cause is named, extend() adds it and
# the gain is measured: held-out CVRMSE of the predictive mean and coverage
# of the true parameters by their 90 % intervals, before and after.
# Usage, from the package root with bayesbem installed:
#   Rscript bench/bench-diagnosis.R [simulators] [shapes] [problems]
#   e.g. embedded,degreeday none,covariate 1-10 (the defaults: all, all, 1-10)
# BENCH_FITS=<folder> keeps each problem's data and fit for later runs (the
# diagnosis is then rerun on them); BENCH_EXTEND=false skips the extensions.
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
arg <- function(k, default) if (length(args) >= k) strsplit(args[k], ",")[[1]] else default
shapes <- c(none = NA, covariate = "^occupancy$", step = "^after_change$",
            region = "^rh > ", interaction = "^rh, where temp > ", multiplicative = "^load")
sims <- arg(1, c("embedded", "degreeday"))
shapes <- shapes[arg(2, names(shapes))]
span <- as.integer(strsplit(arg(3, "1-10"), "-")[[1]])
problems <- seq(span[1], span[length(span)])
held_out <- c(2, 7, 11, 16, 21, 24, 26, 31, 35, 40, 45, 48)
epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")

weather <- local({
  years <- rbind(epw_monthly(epw(2012)), epw_monthly(epw(2013)))
  perturbed <- withr::with_seed(17, transform(years, temp = temp + stats::rnorm(24, sd = 1.5),
                                              rh = rh + stats::rnorm(24, sd = 4),
                                              dni = dni * stats::runif(24, 0.9, 1.1)))
  rbind(years, perturbed)
})

# Degree-days of a month from its mean temperature: a softplus in place of
# max(0, .), for the spread of daily temperatures about the mean.
soft_degree_days <- function(diff, days, spread = 2.5) days * spread * log1p(exp(diff / spread))

degree_day_simulator <- function(w) {
  parameters <- data.frame(parameter = c("heat_loss", "base_load"), initial = c(250, 2.2),
                           min = c(150, 1.5), max = c(350, 3), unit = c("W/K", "kW"))
  simulator(function(params, x) {
    hours <- 24 * w$days
    heating <- params$heat_loss * 24 * soft_degree_days(15 - x$temp, w$days) / 1000
    cooling <- (params$heat_loss * 24 * soft_degree_days(x$temp - 18, w$days) / 1000 +
                  2 * x$solar * hours / 1000 * (1 + 0.01 * pmax(x$rh - 40, 0))) / 3
    params$base_load * hours + heating + cooling
  }, x = data.frame(temp = w$temp, rh = w$rh, solar = w$dni), parameters = parameters,
  name = "degree-day model (kWh)")
}

make_simulator <- function(kind) {
  switch(kind, embedded = bem_simulator(weather), degreeday = degree_day_simulator(weather))
}
calibrated <- list(embedded = c("equipment_power_density", "infiltration_per_exterior_area"),
                   degreeday = c("heat_loss", "base_load"))

covariates <- withr::with_seed(99, data.frame(
  occupancy = round(stats::runif(48), 2),
  after_change = rep(0:1, c(14, 34)),
  decoy = weather$temp + stats::rnorm(48, sd = 3)
))
effects <- list(
  none = function(d, eta) 0,
  covariate = function(d, eta) 250 * d$occupancy,
  step = function(d, eta) 200 * d$after_change,
  region = function(d, eta) 250 * (d$rh > 47),
  interaction = function(d, eta) 8 * d$rh * (d$temp > 15),
  multiplicative = function(d, eta) 0.1 * eta
)

# The problem's truth, field data and fit to the 36 training months.
make_problem <- function(kind, sim, runs, shape, k) {
  ranges <- sim$parameters[match(calibrated[[kind]], sim$parameters$parameter), ]
  truth <- withr::with_seed(500 + k, stats::setNames(
    as.list(stats::runif(nrow(ranges), ranges$min + 0.2 * (ranges$max - ranges$min),
                         ranges$max - 0.2 * (ranges$max - ranges$min))), ranges$parameter))
  field <- simulate_field(sim, truth, covariates = covariates, noise_sd = 15, seed = k)
  field$y <- field$y + effects[[shape]](cbind(sim$x, covariates), attr(field, "simulated"))
  base <- suppressWarnings(
    calibrate(field[-held_out, c("y", "temp", "rh", "solar")], runs, chains = 2, iter = 600,
              seed = k, cores = 2, control = list(adapt_delta = 0.9), refresh = 0),
    classes = "bayesbem_warning_convergence")
  list(truth = truth, field = field, base = base)
}

cached_problem <- function(kind, sim, runs, shape, k) {
  folder <- Sys.getenv("BENCH_FITS")
  file <- file.path(folder, sprintf("diagnosis_%s_%s_%d.rds", kind, shape, k))
  if (nzchar(folder) && file.exists(file)) return(readRDS(file))
  problem <- make_problem(kind, sim, runs, shape, k)
  if (nzchar(folder)) saveRDS(problem, file)
  problem
}

one_problem <- function(kind, sim, runs, shape, k) {
  problem <- cached_problem(kind, sim, runs, shape, k)
  truth <- problem$truth
  field <- problem$field
  base <- problem$base
  ex <- explain_discrepancy(base, covariates[-held_out, ], n_null = 1000, seed = k)
  named <- ex$candidate[ex$explains]
  ambiguous <- attr(ex, "ambiguous")
  is_right <- function(name) !is.na(shapes[[shape]]) && grepl(shapes[[shape]], name)
  right <- length(named) > 0 && is_right(named[1])
  scores <- function(f) {
    pred <- predict(f, field[held_out, c("temp", "rh", "solar", names(covariates))])
    s <- summary(f)$parameters
    c(cvrmse = cvrmse(field$y[held_out], pred$mean),
      covered = sum(s$q5 <= unlist(truth)[rownames(s)] & unlist(truth)[rownames(s)] <= s$q95))
  }
  before <- scores(base)
  after <- if (right && Sys.getenv("BENCH_EXTEND") != "false") {
    scores(suppressWarnings(extend(base, with = named[1], covariates = covariates[-held_out, ],
                                   refresh = 0), classes = "bayesbem_warning_convergence"))
  } else {
    c(cvrmse = NA, covered = NA)
  }
  data.frame(simulator = kind, shape = shape, problem = k,
             named = if (length(named) > 0) named[1] else "nothing",
             ambiguous = paste(ambiguous, collapse = "; "),
             right = right && length(ambiguous) == 0,
             right_among_ambiguous = length(ambiguous) > 0 &&
               (right || any(vapply(ambiguous, is_right, logical(1)))),
             wrong = length(named) > 0 && !right &&
               !any(vapply(ambiguous, is_right, logical(1))),
             cvrmse_before = before[["cvrmse"]], cvrmse_after = after[["cvrmse"]],
             covered_before = before[["covered"]], covered_after = after[["covered"]],
             parameters = length(truth))
}

rows <- list()
for (kind in sims) {
  sim <- make_simulator(kind)
  ranges <- sim$parameters[match(calibrated[[kind]], sim$parameters$parameter), ]
  runs <- simulate_design(sim, design_lhs(ranges, n = 30, seed = 1))
  for (shape in names(shapes)) for (k in problems) {
    start <- proc.time()[["elapsed"]]
    row <- one_problem(kind, sim, runs, shape, k)
    row$seconds <- proc.time()[["elapsed"]] - start
    print(row, row.names = FALSE, digits = 3)
    rows[[length(rows) + 1L]] <- row
  }
}
out <- do.call(rbind, rows)
summary_rows <- lapply(split(out, list(out$simulator, out$shape), drop = TRUE), function(s) {
  data.frame(simulator = s$simulator[1], shape = s$shape[1], problems = nrow(s),
             some_cause_named = sum(s$named != "nothing"), named_right = sum(s$right),
             ambiguous_with_right = sum(s$right_among_ambiguous), named_wrong = sum(s$wrong),
             cvrmse_before = if (any(s$right)) stats::median(s$cvrmse_before[s$right]) else NA,
             cvrmse_after = if (any(s$right)) stats::median(s$cvrmse_after[s$right]) else NA,
             covered_before = sprintf("%d/%d", sum(s$covered_before[s$right]), sum(s$parameters[s$right])),
             covered_after = sprintf("%d/%d", sum(s$covered_after[s$right]), sum(s$parameters[s$right])))
})
cat("\nPer simulator and shape (CVRMSE %: held-out median over problems named right; covered: true parameters inside their 90 % intervals, problems named right):\n")
print(do.call(rbind, summary_rows), row.names = FALSE, digits = 3)
nulls <- out[out$shape == "none", ]
if (nrow(nulls) > 0) {
  cat(sprintf("false alarms: %d of %d null data sets (%.1f %%)\n", sum(nulls$named != "nothing"),
              nrow(nulls), 100 * mean(nulls$named != "nothing")))
}
cat(sprintf("machine: %d cores; R %s; rstan %s; %s\n", parallel::detectCores(), getRversion(),
            packageVersion("rstan"), Sys.Date()))
