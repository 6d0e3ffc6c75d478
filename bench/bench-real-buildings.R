# Benchmark: real buildings as their data come. Buildings of the Cambridge
# University Estates building energy archive (Langtry & Choudhary 2024,
# doi 10.5281/zenodo.10955332, MIT): a year of hourly electricity and gas
# per building (UTC, missing readings stored as zeros, clipped at 10 x the
# mean) and the Met Office's hourly weather at Bedford (temperature,
# relative humidity, global radiation). Each building: the station's table
# through read_weather() and write_epw(), each meter through
# field_hours() with meter_rules() (gas: no zero rule, a gas meter rests
# in summer), train January-September, predict October-December with the
# TOWT baseline; hourly and monthly CV(RMSE), NMBE and 90 % coverage of
# the held-out hours and months, and what the rules left out
# (bench/results/real-buildings.md). With BENCH_CALIBRATE=true (or a
# list of meters, e.g. electricity), each meter is also calibrated on its
# own: the embedded hourly model of an uncooled building of the archive's
# floor area, floors and roof area (building_floor_roof_areas.csv) on
# London's clock, its occupancy and its loads' mean share estimated from
# the training months' readings (meter_occupancy(), meter_load_fraction()),
# its heating on the timer its gas meter's winter profile shows
# (meter_heating_schedule()), a university's loads centred on its
# metered electricity per m2 (bem_parameters(type =, electricity =)), a
# ventilation-only fan; 30 runs over the three parameters that move the
# meter most, calibrate()'s defaults on January-September, and
# compare_baseline() on October-December, with the fit's wall time; a
# meter no run reaches is reported with calibrate()'s refusal.
# BENCH_FITS=<folder> keeps the fits.
# Buildings 19, 57 and 111 are kept for acceptance and refused here.
# Usage, from the package root, with bayesbem installed:
#   BENCH_ARCHIVE=<the archive's git directory or checkout> \
#     Rscript bench/bench-real-buildings.R [buildings] [year]
#   (default buildings 0,13,22,25,27,33,35,40; year 2019)
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
buildings <- if (length(args) > 0L) strsplit(args[1], ",")[[1]] else
  c("0", "13", "22", "25", "27", "33", "35", "40")
year <- if (length(args) > 1L) args[2] else "2019"
archive <- Sys.getenv("BENCH_ARCHIVE")
if (!nzchar(archive)) stop("set BENCH_ARCHIVE to the archive's folder", call. = FALSE)
source(file.path("bench", "archive.R"))
refuse_held_out(buildings)
epw <- archive_epw(year)
sim <- bem_simulator(epw, by = "hour")
calibrate_meters <- strsplit(Sys.getenv("BENCH_CALIBRATE"), ",")[[1]]
if (identical(calibrate_meters, "true")) calibrate_meters <- c("electricity", "gas")
fits_dir <- Sys.getenv("BENCH_FITS")
if (nzchar(fits_dir)) dir.create(fits_dir, showWarnings = FALSE, recursive = TRUE)
zone <- "Europe/London"
held_out <- function(time) as.integer(format(time, "%m", tz = zone)) >= 10L

score <- function(obs, pred, lower, upper) {
  c(cvrmse = cvrmse(obs, pred), nmbe = nmbe(obs, pred),
    coverage = mean(obs >= lower & obs <= upper))
}

# What each meter's runs vary: the three parameters that move the
# electricity most; the heating's set point, burner and infiltration.
varied <- list(electricity = c("equipment_power_density", "lighting_power_density",
                               "fan_total_efficiency"),
               gas = c("heating_setpoint", "gas_burner_efficiency",
                       "infiltration_per_exterior_area"))

# The embedded model of building `b` from the archive's facts, calibrated
# on one meter's training hours and scored beside the baseline on the
# held-out ones; a meter no run reaches is reported with calibrate()'s
# refusal (the measured total and the runs' range) instead.
calibrate_building <- function(b, facts, meter_name, field, time, use, baseline, intensity) {
  train_time <- field$time[!held_out(field$time)]
  train_use <- field$y[!held_out(field$time)]
  # the model's lights and equipment then follow the meter's profile, base
  # load included, whatever their densities
  occupancy <- meter_occupancy(train_time, train_use)
  share <- meter_load_fraction(train_time, train_use)
  # a ventilation-only air system, 1 l/s per m2 of floor (10 l/s a person
  # at 10 m2 each), not the case study's all-air 5.7 l/s per m2
  building <- bem_building_facts(facts$floor_area, floors = facts$floors,
                                 roof_area = facts$roof_area, type = "university", clock = zone,
                                 cooling = FALSE, occupancy = occupancy,
                                 fan_flow = 1e-3 * facts$floor_area,
                                 lighting_fraction = share, equipment_fraction = share,
                                 heating_schedule = facts$heating_schedule)
  pars <- bem_parameters(type = "university", electricity = intensity)
  meter <- bem_simulator(epw, parameters = pars, building = building, by = "hour",
                         output = meter_name)
  # the field's inputs on the building's clock, as its runs'
  field <- suppressMessages(field_hours(meter, time, use, rules = meter_rules_of(meter_name),
                                        sufficiency = 0))
  runs <- simulate_design(meter, design_lhs(pars[pars$parameter %in% varied[[meter_name]], ], 30,
                                            seed = 1))
  train <- field[!held_out(field$time), ]
  hours <- match(train$time, meter$periods$start)
  runs <- runs[rep(seq_along(meter$periods$start), 30) %in% hours, ]
  row <- data.frame(building = b, meter = meter_name, floor_area = round(facts$floor_area),
                    kwh_per_m2 = round(sum(field$y) / facts$floor_area))
  started <- proc.time()[["elapsed"]]
  fit <- tryCatch(suppressWarnings(calibrate(train, runs, seed = 1, progress = FALSE)),
                  bayesbem_error_prior_misses = function(e) e)
  seconds <- proc.time()[["elapsed"]] - started
  if (inherits(fit, "error")) {
    cat(sprintf("building %s, %s: %s\n", b, meter_name, cli::ansi_strip(conditionMessage(fit))))
    return(data.frame(row, prediction = "refused", by = NA, n = NA, cvrmse = NA, nmbe = NA,
                      coverage = NA, fit_seconds = round(seconds), rhat = NA))
  }
  if (nzchar(fits_dir)) saveRDS(fit, file.path(fits_dir, sprintf("b%s-%s.rds", b, meter_name)))
  obs <- rep(NA_real_, length(meter$periods$start))
  test <- field[held_out(field$time), ]
  obs[match(test$time, meter$periods$start)] <- test$y
  table <- compare_baseline(fit, baseline, meter, obs)
  data.frame(row, table[c("prediction", "by", "n")],
             round(as.data.frame(table)[c("cvrmse", "nmbe", "coverage")], 3),
             fit_seconds = round(seconds),
             rhat = round(max(check_convergence(fit, warn = FALSE)$rhat), 3))
}

# The heating plant's timer from the gas meter's readings (time, value) of
# the training winter (January-March); around the clock (NULL) without.
heating_timer <- function(gas) {
  if (is.null(gas)) return(NULL)
  time <- as.POSIXct(gas[[1]], tz = "UTC")
  attr(time, "tzone") <- zone
  winter <- as.integer(format(time, "%m", tz = zone)) <= 3L
  meter_heating_schedule(time[winter], gas[[2]][winter])
}

# What stands for a missing reading: a gas meter rests in summer, so runs
# and days of zeros are readings there.
meter_rules_of <- function(meter) {
  if (meter == "gas") meter_rules(zero_hours = Inf, zero_days = FALSE) else meter_rules()
}

calibrated <- list()
rows <- list()
for (b in buildings) {
  facts <- archive_facts(b)
  meters <- lapply(c(electricity = "electricity", gas = "gas"), archive_meter, b = b, year = year)
  facts$heating_schedule <- heating_timer(meters$gas)
  for (meter in names(meters)) {
    readings <- meters[[meter]]
    if (is.null(readings)) next
    time <- as.POSIXct(readings[[1]], tz = "UTC")
    rules <- meter_rules_of(meter)
    said <- character()
    field <- tryCatch(withCallingHandlers(
      field_hours(sim, time, readings[[2]], rules = rules, sufficiency = 0),
      message = function(m) {
        said <<- c(said, conditionMessage(m))
        invokeRestart("muffleMessage")
      },
      warning = function(w) invokeRestart("muffleWarning")), error = function(e) e)
    if (inherits(field, "error")) next
    left_out <- length(time) - nrow(field)
    attr(field$time, "tzone") <- zone
    train <- field[!held_out(field$time), ]
    test <- field[held_out(field$time), ]
    started <- proc.time()[["elapsed"]]
    baseline <- towt_baseline(train)
    hours <- predict(baseline, test)
    months <- predict(baseline, test, by = "month")
    month_obs <- as.vector(tapply(test$y, format(test$time, "%Y-%m", tz = zone), sum))
    rows[[length(rows) + 1L]] <- data.frame(
      building = b, meter = meter, hours = nrow(field), left_out = left_out,
      min_share = round(min(data_sufficiency(field$time)$share), 2),
      t(round(score(test$y, hours$mean, hours$q5, hours$q95), 3)),
      t(round(stats::setNames(score(month_obs, months$mean, months$q5, months$q95),
                              c("m_cvrmse", "m_nmbe", "m_coverage")), 3)),
      seconds = round(proc.time()[["elapsed"]] - started, 1))
    if (meter == "electricity") intensity <- sum(field$y) / facts$floor_area
    if (meter %in% calibrate_meters) {
      calibrated[[length(calibrated) + 1L]] <- calibrate_building(b, facts, meter, field, time,
                                                                  readings[[2]], baseline,
                                                                  intensity)
      print(calibrated[[length(calibrated)]], row.names = FALSE)
    }
  }
}

table <- do.call(rbind, rows)
print(table, row.names = FALSE)
if (length(calibrated) > 0L) print(do.call(rbind, calibrated), row.names = FALSE)
