# Benchmark: what a second meter teaches. Synthetic truth, calibrated on
# electricity alone and on electricity and gas at once, on two simulators:
#   embedded  the package's monthly model (ISO 13790), 2012 and 2013;
#   eplus     the case-study EnergyPlus model by month, 2012 and 2013 (its
#             run period starting on each year's own weekday), one run
#             giving Electricity:Facility and NaturalGas:Facility (needs
#             EnergyPlus).
# Four parameters calibrated: fan total efficiency, equipment power
# density, infiltration and heating setpoint (the others at their initial
# values); per problem the truth is drawn in the middle 80 % of their
# ranges, each meter's noise is 2 % of its mean, and 30 runs (one Latin
# hypercube per simulator) give both meters. Fits: calibrate()'s defaults
# but 2 chains of 2000 iterations. Reported per simulator and fit: each
# parameter's posterior sd over its prior's (median over problems; below
# 0.5 "learnt", above 0.8 "prior-driven", as identifiability() says),
# coverage of the truth by the 90 % interval, fits that pass
# check_convergence(), and the median wall time of a fit.
# `gradient` instead times one gradient of stage 2 (koh.stan with the
# separable emulator, and koh_basis.stan) on electricity alone and on both
# meters, n days of 2013 per meter, 30 runs of the embedded model: the
# cost of a second output per gradient.
# Usage, from the package root with bayesbem installed:
#   Rscript bench/bench-multi-output.R [simulators] [problems]
#   e.g. embedded 1-10 (the defaults: embedded,eplus and 1-10)
#   Rscript bench/bench-multi-output.R gradient [n values, comma-separated]
# BENCH_FITS=<folder> keeps the runs and each problem's results.
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
if (identical(args[1], "gradient")) {
  ns <- if (length(args) > 1) as.integer(strsplit(args[2], ",")[[1]]) else c(36, 120, 365)
  ns_gradient <- ns
}
arg <- function(k, default) if (length(args) >= k) strsplit(args[k], ",")[[1]] else default
kinds <- arg(1, c("embedded", "eplus"))
span <- as.integer(strsplit(arg(2, "1-10"), "-")[[1]])
problems <- seq(span[1], span[length(span)])
fits_dir <- Sys.getenv("BENCH_FITS")
if (nzchar(fits_dir)) dir.create(fits_dir, showWarnings = FALSE, recursive = TRUE)
epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
calibrated <- c("fan_total_efficiency", "equipment_power_density",
                "infiltration_per_exterior_area", "heating_setpoint")

embedded_simulator <- function() {
  weather <- rbind(epw_monthly(epw(2012)), epw_monthly(epw(2013)))
  bem_simulator(weather, output = c("electricity", "gas"))
}

eplus_year <- function(year) {
  model <- eplus_model(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
  start <- c("Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday",
             "Saturday")[as.POSIXlt(sprintf("%d-01-01", year))$wday + 1]
  model <- eplus_set(model, "RunPeriod", "Run Period 1", `Day of Week for Start Day` = start)
  eplus_simulator(model, epw(year), by = "month",
                  output = c("Electricity:Facility", "NaturalGas:Facility"))
}
eplus_simulator_2y <- function() {
  years <- lapply(c(2012, 2013), eplus_year)
  simulator(function(params, x) {
    out <- rbind(years[[1]]$fun(params, years[[1]]$x), years[[2]]$fun(params, years[[2]]$x))
    names(out) <- c("electricity", "gas")
    out
  }, x = rbind(years[[1]]$x, years[[2]]$x), parameters = years[[1]]$parameters,
  name = "EnergyPlus case study, 2012-2013 by month, electricity and gas (kWh)")
}

# Runs of one simulator, cached in BENCH_FITS.
simulator_runs <- function(kind, sim) {
  path <- if (nzchar(fits_dir)) file.path(fits_dir, sprintf("runs-%s.rds", kind))
  if (!is.null(path) && file.exists(path)) return(readRDS(path))
  pars <- sim$parameters[sim$parameters$parameter %in% calibrated, ]
  runs <- simulate_design(sim, design_lhs(pars, 30, seed = 11))
  if (!is.null(path)) saveRDS(runs, path)
  runs
}

# One problem: its truth and field data, and the two fits' summaries.
run_problem <- function(kind, sim, runs, k) {
  path <- if (nzchar(fits_dir)) file.path(fits_dir, sprintf("%s-%d.rds", kind, k))
  if (!is.null(path) && file.exists(path)) return(readRDS(path))
  pars <- sim$parameters[match(calibrated, sim$parameters$parameter), ]
  set.seed(100 + k)
  truth <- stats::setNames(as.list(pars$min + stats::runif(nrow(pars), 0.1, 0.9) * (pars$max - pars$min)),
                           pars$parameter)
  clean <- simulate_field(sim, truth)
  means <- tapply(clean$y, clean$output, mean)
  field <- simulate_field(sim, truth, noise_sd = 0.02 * means, seed = 200 + k)
  electricity <- function(d) d[d$output == "electricity", names(d) != "output"]
  fits <- list(electricity = function() calibrate(electricity(field), electricity(runs), chains = 2,
                                                  iter = 2000, seed = 300 + k),
               both = function() calibrate(field, runs, chains = 2, iter = 2000, seed = 300 + k))
  rows <- lapply(names(fits), function(name) {
    time <- system.time(fit <- suppressWarnings(suppressMessages(fits[[name]]())))[["elapsed"]]
    one <- if (name == "both") output_fit(fit, "electricity") else fit
    draws <- posterior::as_draws_matrix(posterior::as_draws(one))[, calibrated]
    conv <- check_convergence(fit, warn = FALSE)
    sampler <- attr(conv, "sampler")
    ok <- all(conv$ok) && sampler$divergent == 0 && sampler$treedepth_hits == 0 &&
      all(sampler$ebfmi >= 0.3)
    data.frame(kind = kind, problem = k, fit = name, parameter = calibrated,
               truth = unlist(truth[calibrated]),
               sd_ratio = apply(draws, 2, stats::sd) / ((pars$max - pars$min) / sqrt(12)),
               covered = vapply(seq_along(calibrated), function(j) {
                 q <- stats::quantile(draws[, j], c(0.05, 0.95))
                 truth[[j]] >= q[1] && truth[[j]] <= q[2]
               }, logical(1)),
               converged = ok, seconds = time, row.names = NULL)
  })
  out <- do.call(rbind, rows)
  if (!is.null(path)) saveRDS(out, path)
  out
}

# ms per gradient of stage 2 at one point (mean over about a second of calls).
gradient_ms <- function(program, data) {
  utils::capture.output(fit0 <- rstan::sampling(bayesbem:::stanmodels[[program]], data = data,
                                                chains = 0))
  u <- rep(0.1, rstan::get_num_upars(fit0))
  one <- system.time(rstan::grad_log_prob(fit0, u))[["elapsed"]]
  reps <- max(3L, ceiling(1 / max(one, 1e-3)))
  1000 * system.time(for (i in seq_len(reps)) rstan::grad_log_prob(fit0, u))[["elapsed"]] / reps
}
gradient_table <- function(ns) {
  daily <- epw_daily(epw(2013))
  priors <- koh_priors()
  rows <- lapply(ns, function(n) {
    sim <- bem_simulator(daily[unique(round(seq(1, nrow(daily), length.out = n))), ],
                         output = c("electricity", "gas"))
    pars <- sim$parameters[sim$parameters$parameter %in% calibrated, ]
    field <- simulate_field(sim, list(equipment_power_density = 15), noise_sd = 1, seed = 1)
    runs <- simulate_design(sim, design_lhs(pars, 30, seed = 2))
    both <- koh_data(field, runs)
    one <- both$outputs$electricity
    emulator <- function(d) {
      list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
           b = numeric(sum(bayesbem:::mean_selection(priors, d$p, d$q))),
           basis = bayesbem:::basis_emulator(d))
    }
    ems <- lapply(both$outputs, emulator)
    ms <- function(d, em) {
      c(separable = gradient_ms("koh", bayesbem:::modular_stan_data(d, priors, em)),
        basis = gradient_ms("koh_basis", bayesbem:::basis_stan_data(d, priors, em)))
    }
    a <- ms(one, ems$electricity)
    b <- ms(both, ems)
    data.frame(n_per_meter = n, separable_1 = a[["separable"]], separable_2 = b[["separable"]],
               basis_1 = a[["basis"]], basis_2 = b[["basis"]])
  })
  out <- do.call(rbind, rows)
  cat(sprintf("\nbench-multi-output.R gradient, %s; %s\nms per stage-2 gradient, one meter (_1) and two (_2):\n",
              format(Sys.Date()), extSoftVersion()[["BLAS"]]))
  print(out, digits = 3, row.names = FALSE)
}
if (exists("ns_gradient")) {
  gradient_table(ns_gradient)
  quit(save = "no")
}

results <- do.call(rbind, lapply(kinds, function(kind) {
  sim <- if (kind == "eplus") eplus_simulator_2y() else embedded_simulator()
  runs <- simulator_runs(kind, sim)
  do.call(rbind, lapply(problems, function(k) {
    r <- run_problem(kind, sim, runs, k)
    message(sprintf("%s %d done", kind, k))
    r
  }))
}))

short <- c(fan_total_efficiency = "fan", equipment_power_density = "EPD",
           infiltration_per_exterior_area = "infiltration", heating_setpoint = "heating sp")
cat(sprintf("\nbench-multi-output.R, %s; %s; %d problems per simulator\n", format(Sys.Date()),
            extSoftVersion()[["BLAS"]], length(problems)))
for (kind in unique(results$kind)) {
  cat(sprintf("\n%s\n", kind))
  table <- do.call(rbind, lapply(c("electricity", "both"), function(f) {
    r <- results[results$kind == kind & results$fit == f, ]
    per <- vapply(calibrated, function(p) {
      s <- r[r$parameter == p, ]
      sprintf("%.2f (%d/%d)", stats::median(s$sd_ratio), sum(s$covered), nrow(s))
    }, character(1))
    fits <- unique(r[c("problem", "converged", "seconds")])
    data.frame(fit = if (f == "both") "electricity + gas" else "electricity",
               t(stats::setNames(per, short[calibrated])),
               converged = sprintf("%d/%d", sum(fits$converged), nrow(fits)),
               seconds = round(stats::median(fits$seconds)), check.names = FALSE)
  }))
  print(table, row.names = FALSE)
  cover <- results[results$kind == kind, ]
  cat(sprintf("coverage over all parameters: electricity %d/%d, both %d/%d\n",
              sum(cover$covered[cover$fit == "electricity"]), sum(cover$fit == "electricity"),
              sum(cover$covered[cover$fit == "both"]), sum(cover$fit == "both")))
}
cat("\nEach parameter: median posterior sd / prior sd (truth covered by the 90 % interval).\n")
