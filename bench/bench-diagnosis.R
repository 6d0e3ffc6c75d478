# Benchmark: does explain_discrepancy() name the cause on problems it was
# not tuned on? Written apart from the test suite's synthetic problems
# (tests/testthat/helper-synthetic.R), with simulators of different forms:
#   embedded     the package's monthly model (ISO 13790), equipment power
#                density and infiltration calibrated; 48 months of weather
#                (2012, 2013 and a perturbed copy of both), 36 fitted;
#   degreeday    a model written here: base load plus heating and cooling
#                by degree-days with a soft balance point, solar gains
#                through the cooling plant; heat loss coefficient and base
#                load calibrated; the same 48 months;
#   eplus        the case-study EnergyPlus model by month, 2012 and 2013,
#                equipment power density and cooling COP calibrated, 18
#                months fitted, 6 held out (needs EnergyPlus);
#   eplus_daily  the same by day, every other day of 2013, 153 fitted, 30
#                held out;
#   eplus_hourly the same by hour, twelve weeks of 2013 from 4 March (2,016
#                hours, every one fitted: the additive discrepancy predicts
#                only at its field rows), AR(1) noise (phi 0.7, sd 0.5
#                kWh), the inputs also weekday and daytype_hour.
# Per problem: true parameters drawn in the middle 60 % of their ranges, a
# hidden effect of one shape, noise (sd 15 kWh a month; 40 kWh a month and
# 3 kWh a day on EnergyPlus); 30 runs (one Latin hypercube per simulator;
# 60 by hour, where 30 left the basis emulator's error far from its stated
# size: bench/results/diagnosis.md);
# fits of 2 chains x 600 at adapt_delta 0.9. Shapes and the names that
# count as right:
#   none            no effect (a false alarm is any cause named)
#   covariate       250 kWh x occupancy                  "occupancy"
#   step            200 kWh from month 15 (EnergyPlus: 13) on "after_change"
#   region          250 kWh where rh > 47                "rh > ..."
#   interaction     8 kWh per % rh, where temp > 15      "rh, where temp > ..."
#   multiplicative  10 % of the simulator's output       (no candidate names it)
#   hinge           5 kWh per W/m2 of solar below 220 (lighting below a
#                   daylight threshold)                  "max(... - solar, 0)"
#   line            150 + 10 (rh - 40) kWh where temp > 15 (a latent load,
#                   offset and slope)                    "rh, where temp > ..."
#                   (hinge and line a thirtieth of these by day)
#   weekend         EnergyPlus made with the plug loads on the weekday
#                   schedule at weekends                 "weekend_days", "weekend"
#                   (by hour also a region of weekend hours: "daytype_hour
#                   > c" with c >= 24, "weekday > 5...", or a line of the
#                   hour there)
#   drift           EnergyPlus made with the cooling setpoint 2 C lower in
#                   2013                                 "after_change..."
# The candidates: the inputs, occupancy, after_change, a decoy that follows
# temperature and, on EnergyPlus, the weekend days of each month (or whether
# a day is one; by hour, the hour and whether it is a weekend's). When the
# right cause is named, extend() adds it and the gain is measured: held-out
# CVRMSE of the predictive mean and coverage of the true parameters by
# their 90 % intervals, before and after (not by hour: no held-out rows).
# `in_span`: the share of the effect that recalibration can produce, which
# no diagnosis can tell from parameter error.
# Usage, from the package root with bayesbem installed:
#   Rscript bench/bench-diagnosis.R [simulators] [shapes] [problems]
#   e.g. embedded,degreeday none,covariate 1-10 (the defaults: all, all, 1-10)
# BENCH_FITS=<folder> keeps the runs and each problem's data and fit for
# later runs (the diagnosis is then rerun on them); BENCH_EXTEND=false skips
# the extensions. BENCH_REDRAW=<r> also tests the diagnosis's null alone on
# each null problem: r new noise draws added to the simulator's output at
# the truth, explained with the problem's fit kept (its field outputs
# replaced, scaled as the fit scales them; not refitted), so that false
# alarms are counted over many noise draws at the cost of a diagnosis each.
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
`%||%` <- rlang::`%||%`
args <- commandArgs(trailingOnly = TRUE)
arg <- function(k, default) if (length(args) >= k) strsplit(args[k], ",")[[1]] else default
patterns <- c(none = NA, covariate = "^occupancy$", step = "^after_change$",
              region = "^rh > ", interaction = "^rh, where temp > ", multiplicative = "^load",
              hinge = "^max\\([0-9.]+ - solar, 0\\)$", line = "^rh, where temp > ",
              weekend = "^weekend", drift = "^after_change")
kind_shapes <- list(embedded = names(patterns)[1:8], degreeday = names(patterns)[1:8],
                    eplus = c("none", "covariate", "step", "hinge", "line", "weekend", "drift"),
                    eplus_daily = c("none", "hinge", "line", "weekend"),
                    eplus_hourly = c("none", "weekend"))
sims <- arg(1, names(kind_shapes))
shapes_asked <- arg(2, names(patterns))
span <- as.integer(strsplit(arg(3, "1-10"), "-")[[1]])
problems <- seq(span[1], span[length(span)])
epw <- function(year) system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
fits_dir <- Sys.getenv("BENCH_FITS")

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

# The EnergyPlus virtual building: the shipped case-study model, its week
# starting on the weather year's own weekday (the model's run period starts
# every year on a Sunday), with two parameters that make faults and that
# the calibration leaves at their initial 0: `weekend_fault`, a measure
# that runs the plug loads on weekends on the weekday schedule (equipment
# left on), and `setpoint_drift`, degrees by which the cooling setpoint is
# lower in 2013 than in 2012.
eplus_parameters <- unique(eplus_parameter_map()[c("parameter", "initial", "min", "max")])
eplus_parameters <- rbind(eplus_parameters,
                          data.frame(parameter = "weekend_fault", initial = 0, min = 0, max = 1))
weekend_as_weekdays <- function(model, value) {
  if (value < 0.5) return(model)
  weekday <- "Building Plug Load Default Weekday Schedule"
  eplus_set(model, "Schedule:Week:Daily", "Schedule:Week:Daily {80047a7a-8e87-413e-a5e3-e7748404cf92}",
            `Saturday Schedule:Day Name` = weekday, `Sunday Schedule:Day Name` = weekday)
}
eplus_year <- function(year, by) {
  model <- eplus_model(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
  start <- c("Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday",
             "Saturday")[as.POSIXlt(sprintf("%d-01-01", year))$wday + 1]
  model <- eplus_set(model, "RunPeriod", "Run Period 1", `Day of Week for Start Day` = start)
  eplus_simulator(model, epw(year), parameters = eplus_parameters, by = by,
                  measures = list(weekend_fault = weekend_as_weekdays))
}
eplus_monthly_simulator <- function() {
  years <- lapply(c(2012, 2013), eplus_year, by = "month")
  drift <- data.frame(parameter = "setpoint_drift", initial = 0, min = 0, max = 3)
  simulator(function(params, x) {
    later <- params
    later$cooling_setpoint <- params$cooling_setpoint - params$setpoint_drift
    params$setpoint_drift <- later$setpoint_drift <- NULL
    c(years[[1]]$fun(params, years[[1]]$x), years[[2]]$fun(later, years[[2]]$x))
  }, x = rbind(years[[1]]$x, years[[2]]$x), parameters = rbind(eplus_parameters, drift),
  name = "EnergyPlus case study, 2012-2013 by month (kWh)")
}
# Every other day of 2013 (183 days).
eplus_days <- seq(1, 365, by = 2)
eplus_daily_simulator <- function() {
  year <- eplus_year(2013, "day")
  simulator(function(params, x) year$fun(params, year$x)[eplus_days],
            x = year$x[eplus_days, ], parameters = eplus_parameters,
            name = "EnergyPlus case study, every other day of 2013 (kWh)")
}

# Twelve weeks of 2013's hours from Monday 4 March.
eplus_hours <- 24 * 62 + seq_len(24 * 84)
eplus_hourly_simulator <- function() {
  year <- eplus_year(2013, "hour")
  simulator(function(params, x) year$fun(params, year$x)[eplus_hours],
            x = year$x[eplus_hours, ], parameters = eplus_parameters,
            periods = year$periods[eplus_hours, ],
            name = "EnergyPlus case study, twelve weeks of 2013 by hour (kWh)")
}
# Stationary AR(1) noise: the recursion starts from a unit-variance draw.
ar1_noise <- function(n, phi, sd) {
  sd * as.numeric(stats::filter(stats::rnorm(n, sd = sqrt(1 - phi^2)), phi,
                                method = "recursive", init = stats::rnorm(1)))
}

# Per simulator: the simulator, the calibrated parameters, the candidates
# (covariates), the held-out rows and the noise sd.
make_setting <- function(kind) {
  sim <- switch(kind, embedded = bem_simulator(weather), degreeday = degree_day_simulator(weather),
                eplus = eplus_monthly_simulator(), eplus_daily = eplus_daily_simulator(),
                eplus_hourly = eplus_hourly_simulator())
  n <- nrow(sim$x)
  setting <- switch(kind,
    eplus = list(calibrated = c("equipment_power_density", "dx_cooling_cop"),
                 held_out = c(2, 7, 11, 16, 21, 24), noise_sd = 40, change = 13,
                 calendar = function() {
                   days <- seq(as.Date("2012-01-01"), as.Date("2013-12-31"), by = "day")
                   weekend <- as.POSIXlt(days)$wday %in% c(0, 6)
                   data.frame(weekend_days = as.vector(tapply(weekend, format(days, "%Y-%m"), sum)))
                 }),
    eplus_daily = list(calibrated = c("equipment_power_density", "dx_cooling_cop"),
                       held_out = seq(3, n, by = 6), noise_sd = 3, change = 92, scale = 1 / 30,
                       calendar = function() {
                         days <- as.Date("2013-01-01") + eplus_days - 1
                         data.frame(weekend = as.numeric(as.POSIXlt(days)$wday %in% c(0, 6)))
                       }),
    eplus_hourly = list(calibrated = c("equipment_power_density", "dx_cooling_cop"),
                        held_out = integer(0), noise_sd = 0, ar1 = c(phi = 0.7, sd = 0.5), n_runs = 60,
                        change = 24 * 42 + 1,
                        inputs = c("temp", "rh", "solar", "weekday", "daytype_hour"),
                        patterns = list(weekend = paste0(
                          "^weekend|^((hour|daytype_hour), where )?",
                          "(weekday > 5|daytype_hour > (2[4-9]|3[0-9]|4[0-6]))")),
                        calendar = function() calendar_covariates(sim)[c("hour", "weekend")]),
    list(calibrated = if (kind == "embedded") c("equipment_power_density", "infiltration_per_exterior_area")
                      else c("heat_loss", "base_load"),
         held_out = c(2, 7, 11, 16, 21, 24, 26, 31, 35, 40, 45, 48), noise_sd = 15, change = 15,
         calendar = function() NULL))
  covariates <- withr::with_seed(99, data.frame(
    occupancy = round(stats::runif(n), 2),
    after_change = as.numeric(seq_len(n) >= setting$change),
    decoy = sim$x$temp + stats::rnorm(n, sd = 3)
  ))
  calendar <- setting$calendar()
  if (!is.null(calendar)) covariates <- cbind(calendar, covariates)
  ranges <- sim$parameters[match(setting$calibrated, sim$parameters$parameter), ]
  runs <- simulate_design(sim, design_lhs(ranges, n = setting$n_runs %||% 30, seed = 1),
                          cache_dir = if (nzchar(fits_dir)) file.path(fits_dir, "runs"))
  c(setting, list(kind = kind, sim = sim, covariates = covariates, ranges = ranges, runs = runs))
}

# Additive effects in the data, and the faults made inside EnergyPlus (as
# the true values of the fault parameters).
effects <- list(
  none = function(d, eta, scale) 0,
  covariate = function(d, eta, scale) 250 * d$occupancy,
  step = function(d, eta, scale) 200 * d$after_change,
  region = function(d, eta, scale) 250 * (d$rh > 47),
  interaction = function(d, eta, scale) 8 * d$rh * (d$temp > 15),
  multiplicative = function(d, eta, scale) 0.1 * eta,
  hinge = function(d, eta, scale) scale * 5 * pmax(220 - d$solar, 0),
  line = function(d, eta, scale) scale * (150 + 10 * (d$rh - 40)) * (d$temp > 15),
  weekend = function(d, eta, scale) 0,
  drift = function(d, eta, scale) 0
)
faults <- list(weekend = list(weekend_fault = 1), drift = list(setpoint_drift = 2))

# The problem's truth, field data and fit to the training rows.
make_problem <- function(st, shape, k) {
  r <- st$ranges
  truth <- withr::with_seed(500 + k, stats::setNames(
    as.list(stats::runif(nrow(r), r$min + 0.2 * (r$max - r$min), r$max - 0.2 * (r$max - r$min))),
    r$parameter))
  field <- simulate_field(st$sim, c(truth, faults[[shape]]), covariates = st$covariates,
                          noise_sd = st$noise_sd, seed = k)
  scale <- if (is.null(st$scale)) 1 else st$scale
  field$y <- field$y + effects[[shape]](field, attr(field, "simulated"), scale)
  columns <- c("y", st$inputs %||% c("temp", "rh", "solar"))
  noise <- "none"
  if (!is.null(st$ar1)) {
    field$y <- field$y + withr::with_seed(k, correlated_noise(st, nrow(field)))
    field$time <- st$sim$periods$start
    columns <- c(columns, "time")
    noise <- "ar1"
  }
  base <- suppressWarnings(
    calibrate(field[training_rows(st), columns], st$runs, chains = 2, iter = 600, seed = k,
              cores = 2, control = list(adapt_delta = 0.9), noise_correlation = noise,
              refresh = 0),
    classes = "bayesbem_warning_convergence")
  list(truth = truth, field = field, base = base)
}

correlated_noise <- function(st, n) ar1_noise(n, st$ar1[["phi"]], st$ar1[["sd"]])

# Alarms of the diagnosis on `draws` new noise draws given a null problem's
# fit: the simulator's output at the truth plus noise as make_problem()
# adds it.
redrawn_alarms <- function(st, problem, train_covariates, k, draws) {
  fit <- problem$base
  sc <- fit$data$scaling
  rows <- training_rows(st)
  simulated <- attr(problem$field, "simulated")[rows]
  sum(vapply(seq_len(draws), function(j) withr::with_seed(1000 * k + j, {
    y <- simulated + stats::rnorm(length(rows), sd = st$noise_sd)
    if (!is.null(st$ar1)) y <- y + correlated_noise(st, length(rows))
    fit$data$y <- (y - sc$y_center) / sc$y_scale
    ex <- explain_discrepancy(fit, train_covariates, n_null = 1000, seed = j)
    any(ex$explains)
  }), logical(1)))
}

# The share of a problem's hidden effect (at the training rows) that lies in
# what recalibration can do, the span explain_discrepancy() projects off
# (design C2): near 1, the data cannot tell the effect from parameter error.
effect_in_span <- function(st, problem, shape) {
  effect <- effects[[shape]](problem$field, attr(problem$field, "simulated"), st$scale %||% 1)
  if (length(effect) == 1L) {
    return(NA_real_)
  }
  effect <- effect[training_rows(st)]
  basis <- asNamespace("bayesbem")$recalibration_geometry(problem$base)$basis
  1 - sum(qr.resid(qr(basis), effect)^2) / sum((effect - mean(effect))^2)
}

training_rows <- function(st) setdiff(seq_len(nrow(st$sim$x)), st$held_out)

cached_problem <- function(st, shape, k) {
  file <- file.path(fits_dir, sprintf("diagnosis_%s_%s_%d.rds", st$kind, shape, k))
  if (nzchar(fits_dir) && file.exists(file)) return(readRDS(file))
  problem <- make_problem(st, shape, k)
  if (nzchar(fits_dir)) saveRDS(problem, file)
  problem
}

one_problem <- function(st, shape, k) {
  problem <- cached_problem(st, shape, k)
  truth <- problem$truth
  field <- problem$field
  base <- problem$base
  train_covariates <- st$covariates[training_rows(st), , drop = FALSE]
  ex <- explain_discrepancy(base, train_covariates, n_null = 1000, seed = k)
  named <- ex$candidate[ex$explains]
  ambiguous <- attr(ex, "ambiguous")
  pattern <- st$patterns[[shape]] %||% patterns[[shape]]
  is_right <- function(name) !is.na(pattern) && grepl(pattern, name)
  right <- length(named) > 0 && is_right(named[1])
  scores <- function(f) {
    if (length(st$held_out) == 0L) {
      return(c(cvrmse = NA, covered = NA))
    }
    pred <- predict(f, field[st$held_out, c("temp", "rh", "solar", names(st$covariates))])
    s <- summary(f)$parameters
    c(cvrmse = cvrmse(field$y[st$held_out], pred$mean),
      covered = sum(s$q5 <= unlist(truth)[rownames(s)] & unlist(truth)[rownames(s)] <= s$q95))
  }
  before <- scores(base)
  after <- if (right && Sys.getenv("BENCH_EXTEND") != "false") {
    scores(suppressWarnings(extend(base, with = named[1], covariates = train_covariates,
                                   refresh = 0), classes = "bayesbem_warning_convergence"))
  } else {
    c(cvrmse = NA, covered = NA)
  }
  redraws <- if (shape == "none") as.integer(Sys.getenv("BENCH_REDRAW", "0")) else 0L
  data.frame(simulator = st$kind, shape = shape, problem = k,
             named = if (length(named) > 0) named[1] else "nothing",
             ambiguous = paste(ambiguous, collapse = "; "),
             right = right && length(ambiguous) == 0,
             right_among_ambiguous = length(ambiguous) > 0 &&
               (right || any(vapply(ambiguous, is_right, logical(1)))),
             wrong = length(named) > 0 && !right &&
               !any(vapply(ambiguous, is_right, logical(1))),
             cvrmse_before = before[["cvrmse"]], cvrmse_after = after[["cvrmse"]],
             covered_before = before[["covered"]], covered_after = after[["covered"]],
             parameters = length(truth), in_span = effect_in_span(st, problem, shape),
             p_value = min(ex$p_value),
             redraws = redraws,
             redrawn_alarms = redrawn_alarms(st, problem, train_covariates, k, redraws))
}

rows <- list()
for (kind in sims) {
  st <- make_setting(kind)
  for (shape in intersect(shapes_asked, kind_shapes[[kind]])) for (k in problems) {
    start <- proc.time()[["elapsed"]]
    row <- one_problem(st, shape, k)
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
             in_span = stats::median(s$in_span),
             cvrmse_before = if (any(s$right)) stats::median(s$cvrmse_before[s$right]) else NA,
             cvrmse_after = if (any(s$right)) stats::median(s$cvrmse_after[s$right]) else NA,
             covered_before = sprintf("%d/%d", sum(s$covered_before[s$right]), sum(s$parameters[s$right])),
             covered_after = sprintf("%d/%d", sum(s$covered_after[s$right]), sum(s$parameters[s$right])))
})
cat("\nPer simulator and shape (in_span: median share of the effect that recalibration can produce; CVRMSE %: held-out median over problems named right; covered: true parameters inside their 90 % intervals, problems named right):\n")
print(do.call(rbind, summary_rows), row.names = FALSE, digits = 3)
nulls <- out[out$shape == "none", ]
if (nrow(nulls) > 0) {
  cat(sprintf("false alarms: %d of %d null data sets (%.1f %%)\n", sum(nulls$named != "nothing"),
              nrow(nulls), 100 * mean(nulls$named != "nothing")))
  # exact p-values fall below a in at most a share a of the nulls
  cat(sprintf("smallest adjusted p-value below 0.05 / 0.1 / 0.2: %d / %d / %d of %d\n",
              sum(nulls$p_value < 0.05), sum(nulls$p_value < 0.1), sum(nulls$p_value < 0.2),
              nrow(nulls)))
  if (sum(nulls$redraws) > 0) {
    cat(sprintf("false alarms given the fits: %d of %d noise draws (%.1f %%)\n",
                sum(nulls$redrawn_alarms), sum(nulls$redraws),
                100 * sum(nulls$redrawn_alarms) / sum(nulls$redraws)))
  }
}
cat(sprintf("machine: %d cores; R %s; rstan %s; %s\n", parallel::detectCores(), getRversion(),
            packageVersion("rstan"), Sys.Date()))
