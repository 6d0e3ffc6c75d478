test_that("a missing EnergyPlus gets a classed error that says how to fix it", {
  expect_false(eplus_available(tempdir()))
  expect_error(eplus_path(tempdir()), class = "bayesbem_error_eplus_missing")
  expect_snapshot(eplus_path("/no/such/EnergyPlus"), error = TRUE,
                  transform = function(x) sub("/no/such/EnergyPlus", "<dir>", x))
})

test_that("the shipped model runs in EnergyPlus and responds to its parameters", {
  skip_if_no_eplus()
  sim <- seb_eplus()
  expect_s3_class(sim, "bayesbem_simulator")
  expect_equal(nrow(sim$parameters), 14)
  out <- simulate_design(sim, data.frame(equipment_power_density = c(21.9, 10)))
  annual <- run_totals(out, 2)
  # the base model's annual electricity (models/README.md: 25,085 kWh)
  expect_equal(annual[1], 25085, tolerance = 1e-3)
  expect_lt(annual[2], annual[1] - 3000)
  expect_equal(out[1:12, c("temp", "rh")], seb_field[c("temp", "rh")], ignore_attr = TRUE)
})

test_that("everyday model changes leave the monthly electricity as it was", {
  skip_if_no_eplus()
  local_eplus_workers()
  base <- simulate_design(seb_eplus(), data.frame(cooling_setpoint = c(23.9, 22)))
  model <- seb_model()
  # sizing periods simulated, hourly and daily meters added
  busy <- eplus_set(model, "SimulationControl", "SimulationControl 1",
                    `Run Simulation for Sizing Periods` = "Yes")
  busy <- eplus_add(busy, "Output:Meter", key_name = "Electricity:Facility",
                    reporting_frequency = "Hourly")
  busy <- eplus_add(busy, "Output:Meter", key_name = "InteriorLights:Electricity",
                    reporting_frequency = "Daily")
  expect_equal(simulate_design(seb_eplus(model = busy), data.frame(cooling_setpoint = c(23.9, 22)))$eta,
               base$eta, tolerance = 1e-6)
  # the cooling setpoint moved to a Schedule:Compact that a measure sets
  compact <- eplus_add(model, "Schedule:Compact", "Cooling Setpoint Compact",
                       schedule_type_limits_name = "Thermostat Cooling Setpoint Schedule Type Limits",
                       data = list(list(field = "Through: 12/31"),
                                   list(field = "For: SummerDesignDay WinterDesignDay"),
                                   list(field = "Until: 24:00"), list(field = 22.7777777777778),
                                   list(field = "For: AllOtherDays"),
                                   list(field = "Until: 24:00"), list(field = 23.9)))
  compact <- eplus_set(compact, "ThermostatSetpoint:DualSetpoint", "Single zone Thermostat",
                       `Cooling Setpoint Temperature Schedule Name` = "Cooling Setpoint Compact")
  measure <- list(cooling_setpoint = function(model, value) {
    eplus_set(model, "Schedule:Compact", "Cooling Setpoint Compact", `Field 7` = value)
  })
  map <- eplus_parameter_map()
  sim <- seb_eplus(model = compact, map = map[!startsWith(map$parameter, "cooling"), ],
                   measures = measure, parameters = seb_eplus()$parameters)
  expect_equal(simulate_design(sim, data.frame(cooling_setpoint = c(23.9, 22)))$eta, base$eta,
               tolerance = 1e-6)
  # a Schedule:File with a relative path, read from the model's folder, in
  # place of the constant activity-level schedule
  folder <- withr::local_tempdir()
  writeLines(as.character(rep(139.882806752418, 8760)), file.path(folder, "activity.csv"))
  filed <- eplus_del(model, "Schedule:Constant", "Schedule Constant 1")
  filed <- eplus_add(filed, "Schedule:File", "Schedule Constant 1", file_name = "activity.csv",
                     column_number = 1, rows_to_skip_at_top = 0,
                     schedule_type_limits_name = "ActivityLevel")
  eplus_save(filed, file.path(folder, "model.idf"))
  withr::with_dir(tempdir(), {
    sim <- seb_eplus(model = file.path(folder, "model.idf"))
    expect_equal(simulate_design(sim, data.frame(cooling_setpoint = 23.9))$eta, base$eta[1:12],
                 tolerance = 1e-6)
  })
})

test_that("the parameter map is checked by EnergyPlus at both ends of the ranges", {
  skip_if_no_eplus()
  map <- eplus_parameter_map()
  map$object_name[1] <- "No Such Schedule"
  expect_snapshot(seb_eplus(map = map), error = TRUE)
  map <- eplus_parameter_map()
  map$field[5] <- "Fan Efficiency"
  expect_snapshot(seb_eplus(map = map), error = TRUE)
  map <- eplus_parameter_map()
  map$min[map$parameter == "fan_total_efficiency"] <- -0.5
  expect_error(seb_eplus(map = map), class = "bayesbem_error_eplus_run")
  map <- eplus_parameter_map()
  map$apply[1] <- "add"
  expect_error(seb_eplus(map = map), class = "bayesbem_error_parameters")
  # a number for a field that takes a choice: EnergyPlus's converter says so
  map <- eplus_parameter_map()
  map$field[map$parameter == "lighting_power_density"] <- "Design Level Calculation Method"
  expect_snapshot(seb_eplus(map = map), error = TRUE)
  expect_error(seb_eplus(measures = list(nothing = function(model, value) model)),
               class = "bayesbem_error_parameters")
})

test_that("a field that acts only under a calculation method is set with it or refused", {
  skip_if_no_eplus()
  model <- eplus_set(seb_model(), "Lights", "AllLights",
                     `Design Level Calculation Method` = "LightingLevel", `Lighting Level` = 5000)
  map <- eplus_parameter_map()
  expect_message(sim <- seb_eplus(model = model, map = map), "Watts/Area")
  base <- simulate_design(seb_eplus(), data.frame(lighting_power_density = 10))
  expect_equal(simulate_design(sim, data.frame(lighting_power_density = 10))$eta, base$eta,
               tolerance = 1e-6)
  map$apply[map$parameter == "lighting_power_density"] <- "multiply"
  map[map$parameter == "lighting_power_density", c("initial", "min", "max")] <- list(1, 0.5, 1.5)
  expect_snapshot(seb_eplus(model = model, map = map), error = TRUE)
})

test_that("gas is an output like electricity", {
  skip_if_no_eplus()
  gas <- seb_eplus(output = "NaturalGas:Facility")
  out <- simulate_design(gas, data.frame(heating_setpoint = c(15, 20)))
  # the furnace burns gas in winter: more at the higher heating setpoint
  expect_gt(sum(out$eta[13:24]), sum(out$eta[1:12]))
  expect_gt(out$eta[1], out$eta[7])
  run <- eplus_run(seb_model(), shipped_epw(2013))
  monthly <- eplus_output(run, "NaturalGas:Facility", by = "month")
  base <- simulate_design(gas, data.frame(heating_setpoint = 18.3))
  expect_equal(base$eta, monthly$value, tolerance = 1e-6)
})

test_that("a meter is summed over the data's own periods", {
  skip_if_no_eplus()
  bills <- data.frame(start = as.Date(c("2013-01-05", "2013-02-04")),
                      end = as.Date(c("2013-02-03", "2013-03-03")))
  billed <- simulate_design(seb_eplus(periods = bills), data.frame(heating_setpoint = 18.3))
  daily <- simulate_design(seb_eplus(by = "day"), data.frame(heating_setpoint = 18.3))$eta
  dates <- seq(as.Date("2013-01-01"), by = "day", length.out = 365)
  expect_equal(billed$eta, c(sum(daily[dates >= bills$start[1] & dates <= bills$end[1]]),
                             sum(daily[dates >= bills$start[2] & dates <= bills$end[2]])),
               tolerance = 1e-6)
  expect_equal(billed$days, c(30, 28))
  expect_error(seb_eplus(by = "day", periods = bills), class = "bayesbem_error_argument")
})

test_that("a failed run keeps the others and quotes EnergyPlus; the cache sees the model", {
  skip_if_no_eplus()
  sim <- seb_eplus()
  base <- stats::setNames(as.list(sim$parameters$initial), sim$parameters$parameter)
  expect_error(sim$fun(utils::modifyList(base, list(fan_total_efficiency = -1)), sim$x),
               class = "bayesbem_error_eplus_run")
  slow <- seb_eplus(timeout = 1)
  expect_warning(out <- simulate_design(slow, data.frame(equipment_power_density = 10)),
                 class = "bayesbem_warning_simulation")
  expect_match(attr(out, "failed")$error, "time limit")
  cache <- withr::local_tempdir()
  design <- data.frame(equipment_power_density = 15)
  first <- simulate_design(sim, design, cache_dir = cache)
  other <- seb_eplus(model = eplus_set(seb_model(), "Lights", "AllLights",
                                       `Watts per Floor Area` = 5), map = eplus_parameter_map()[-27, ],
                     parameters = sim$parameters[sim$parameters$parameter != "lighting_power_density", ])
  second <- simulate_design(other, design, cache_dir = cache)
  expect_lt(sum(second$eta), sum(first$eta) - 500)
})

# The one-zone example of EnergyPlus (no HVAC, no facility meter): its mean
# zone air temperature from its equipment gain and roof insulation.
one_zone_map <- function() {
  data.frame(parameter = c("equipment_gain", "roof_r_value"),
             object_type = c("OtherEquipment", "Material:NoMass"),
             object_name = c("Test 352a", "R31LAYER"),
             field = c("Design Level", "Thermal Resistance"), apply = "value",
             initial = c(352, 5.456), min = c(0, 2), max = c(1500, 8))
}

one_zone <- function(...) {
  path <- example_model_path("1ZoneUncontrolled_25_2.idf")
  eplus_simulator(path, shipped_epw(2013),
                  map = one_zone_map(), output = "Zone Mean Air Temperature", ...)
}

test_that("a zone temperature is averaged over months and days (1ZoneUncontrolled)", {
  monthly <- one_zone()
  daily <- one_zone(by = "day")
  design <- data.frame(equipment_gain = c(352, 1000))
  m <- simulate_design(monthly, design)
  d <- simulate_design(daily, design)
  expect_equal(nrow(d), 2 * 365)
  # monthly means are the day-weighted means of the daily means
  days <- epw_monthly(shipped_epw(2013))$days
  month <- rep(rep(seq_len(12), days), 2)
  run <- rep(1:2, each = 365)
  expect_equal(m$eta, as.vector(tapply(d$eta, list(month, run), mean)), tolerance = 1e-9)
  # more internal gain, a warmer zone in every month
  expect_true(all(m$eta[13:24] > m$eta[1:12] + 1))
  # weeks: seven days from the first record (the last one shorter)
  weekly <- simulate_design(one_zone(by = "week"), design[1, , drop = FALSE])
  week <- (seq_len(365) - 1) %/% 7 + 1
  expect_equal(weekly$eta, as.vector(tapply(d$eta[1:365], week, mean)), tolerance = 1e-9)
  # the data's own periods, with a gap: the means of their days
  bills <- data.frame(start = as.Date(c("2013-01-05", "2013-02-04", "2013-05-01")),
                      end = as.Date(c("2013-02-03", "2013-03-05", "2013-05-28")))
  billed <- one_zone(periods = bills)
  expect_equal(billed$x$days, c(30, 30, 28))
  b <- simulate_design(billed, design[1, , drop = FALSE])
  dates <- seq(as.Date("2013-01-01"), by = "day", length.out = 365)
  period <- findInterval(dates, bills$start)
  period[period == 0 | dates > bills$end[pmax(period, 1)]] <- NA
  expect_equal(b$eta, as.vector(tapply(d$eta[1:365], period, mean)), tolerance = 1e-9)
})

test_that("Morris screening, a Latin hypercube, calibration and the closed loop run on EnergyPlus", {
  skip_if_no_eplus()
  skip_if_not_installed("sensitivity")
  # five of the model's parameters: Morris's 2 (5 + 1) runs
  screened <- c("equipment_power_density", "lighting_power_density", "heating_setpoint",
                "wall_R_multiplier", "roof_R_multiplier")
  map <- eplus_parameter_map()
  sim <- seb_eplus(map = map[map$parameter %in% screened, ])
  local_eplus_workers()
  m <- screen_morris(sim, r = 2, seed = 1)
  expect_equal(nrow(m), 5)
  top <- m$parameter[m$rank <= 3]
  # plug loads dominate the electricity of this building
  expect_true("equipment_power_density" %in% top)
  design <- design_lhs(sim$parameters[sim$parameters$parameter %in% top, ], n = 10, seed = 2)
  table <- simulate_design(sim, design)
  expect_equal(nrow(table), 120)
  field <- data.frame(y = seb_field$y, sim$x)
  fit <- suppressWarnings(calibrate(field, table, chains = 1, iter = 300, seed = test_seed(3), refresh = 0),
                          classes = "bayesbem_warning_convergence")
  expect_setequal(summary(fit)$parameters$variable, top)
  # the same draws' runs: posterior_simulate() reads validate_emulator()'s
  # from the cache, which holds them under their parameter values
  cache <- withr::local_tempdir()
  check <- validate_emulator(fit, sim, ndraws = 4, cache_dir = cache)
  expect_equal(nrow(check$table), 4 * 12)
  expect_type(check$trusted, "logical")
  real <- posterior_simulate(fit, sim, ndraws = 4, summary = FALSE, cache_dir = cache)
  expect_equal(colMeans(real), colMeans(matrix(check$table$simulated, nrow = 4, byrow = TRUE)),
               ignore_attr = TRUE)
})

test_that("a zone temperature is calibrated by month and by day to a known truth", {
  skip_if_no_eplus()
  local_eplus_workers()
  truth <- list(equipment_gain = 800, roof_r_value = 4)
  sim <- one_zone()
  params <- sim$parameters
  design <- design_lhs(params, n = 10, seed = 3)
  runs <- simulate_design(sim, design)
  field <- simulate_field(sim, truth, noise_sd = 0.1, seed = 4)
  fit <- suppressWarnings(calibrate(field[c("y", "temp", "rh", "solar")], runs, chains = 2,
                                    iter = 600, seed = test_seed(5), refresh = 0),
                          classes = "bayesbem_warning_convergence")
  s <- summary(fit)$parameters
  expect_true(s["equipment_gain", "q5"] <= 800 && s["equipment_gain", "q95"] >= 800)
  # the 90 % interval is narrower than the prior's (1350)
  expect_lt(s["equipment_gain", "q95"] - s["equipment_gain", "q5"], 900)
  # daily: 28 days spread over the year, the runs at the same days
  daily <- one_zone(by = "day")
  days <- seq(5, 365, by = 13)
  runs_d <- simulate_design(daily, design)
  runs_d <- runs_d[rep(seq_len(365), 10) %in% days, ]
  field_d <- simulate_field(daily, truth, noise_sd = 0.2, seed = 6)[days, ]
  fit_d <- suppressWarnings(calibrate(field_d[c("y", "temp", "rh", "solar")], runs_d, chains = 2,
                                      iter = 600, seed = test_seed(7), refresh = 0),
                            classes = "bayesbem_warning_convergence")
  s <- summary(fit_d)$parameters
  expect_true(s["equipment_gain", "q5"] <= 800 && s["equipment_gain", "q95"] >= 800)
})
