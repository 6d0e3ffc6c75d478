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
# (bench/results/real-buildings.md). With BENCH_CALIBRATE=true, the
# electricity is also calibrated: the embedded hourly model of an uncooled
# building of four floors on London's clock, its occupancy estimated from
# the training months' readings (meter_occupancy()), its floor area the
# year's electricity over CIBSE TM46's typical 80 kWh/m2 of a university
# campus (the archive gives no floor areas), a ventilation-only fan; 30
# runs over the three parameters that move the electricity most,
# calibrate()'s defaults on January-September, and compare_baseline() on
# October-December, with the fit's wall time.
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
zone <- "Europe/London"
held_out <- function(time) as.integer(format(time, "%m", tz = zone)) >= 10L

score <- function(obs, pred, lower, upper) {
  c(cvrmse = cvrmse(obs, pred), nmbe = nmbe(obs, pred),
    coverage = mean(obs >= lower & obs <= upper))
}

# The embedded model of building `b` calibrated on its training hours and
# scored beside the baseline on the held-out ones.
calibrate_building <- function(b, field, time, use, baseline) {
  area <- sum(field$y) / 80
  train_time <- field$time[!held_out(field$time)]
  occupancy <- meter_occupancy(train_time, field$y[!held_out(field$time)])
  # a ventilation-only air system, 1 l/s per m2 of floor (10 l/s a person
  # at 10 m2 each), not the case study's all-air 5.7 l/s per m2
  building <- bem_building_facts(area, floors = 4, clock = zone, cooling = FALSE,
                                 occupancy = occupancy, fan_flow = 1e-3 * area)
  meter <- bem_simulator(epw, building = building, by = "hour")
  # the field's inputs on the building's clock, as its runs'
  field <- suppressMessages(field_hours(meter, time, use, sufficiency = 0))
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% c("equipment_power_density", "lighting_power_density",
                                     "fan_total_efficiency"), ]
  runs <- simulate_design(meter, design_lhs(pars, 30, seed = 1))
  train <- field[!held_out(field$time), ]
  hours <- match(train$time, meter$periods$start)
  runs <- runs[rep(seq_along(meter$periods$start), 30) %in% hours, ]
  started <- proc.time()[["elapsed"]]
  fit <- suppressWarnings(calibrate(train, runs, seed = 1, progress = FALSE))
  seconds <- proc.time()[["elapsed"]] - started
  obs <- rep(NA_real_, length(meter$periods$start))
  test <- field[held_out(field$time), ]
  obs[match(test$time, meter$periods$start)] <- test$y
  table <- compare_baseline(fit, baseline, meter, obs)
  data.frame(building = b, floor_area = round(area), table[c("prediction", "by", "n")],
             round(as.data.frame(table)[c("cvrmse", "nmbe", "coverage")], 3),
             fit_seconds = round(seconds),
             rhat = round(max(check_convergence(fit, warn = FALSE)$rhat), 3))
}

calibrated <- list()
rows <- list()
for (b in buildings) {
  for (meter in c("electricity", "gas")) {
    readings <- archive_meter(b, meter, year)
    if (is.null(readings)) next
    time <- as.POSIXct(readings[[1]], tz = "UTC")
    rules <- if (meter == "gas") meter_rules(zero_hours = Inf, zero_days = FALSE) else meter_rules()
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
    if (meter == "electricity" && identical(Sys.getenv("BENCH_CALIBRATE"), "true")) {
      calibrated[[length(calibrated) + 1L]] <- calibrate_building(b, field, time, readings[[2]],
                                                                  baseline)
      print(calibrated[[length(calibrated)]], row.names = FALSE)
    }
  }
}

table <- do.call(rbind, rows)
print(table, row.names = FALSE)
if (length(calibrated) > 0L) print(do.call(rbind, calibrated), row.names = FALSE)
