test_that("a run reports its errors file and its outputs from SQLite", {
  skip_if_no_eplus()
  run <- eplus_run(seb_model(), shipped_epw(2013))
  expect_true(run$ok)
  errors <- eplus_errors(run)
  expect_named(errors, c("level", "message"))
  expect_equal(sum(errors$level %in% c("Severe", "Fatal")), 0)
  expect_match(errors$message[1], "Timestep: Requested number \\(1\\)")
  monthly <- eplus_output(run, "Electricity:Facility", by = "month")
  # the base model's annual electricity (models/README.md: 25,085 kWh)
  expect_equal(sum(monthly$value), 25085, tolerance = 1e-3)
  expect_equal(attr(monthly, "units"), "kWh")
  expect_error(eplus_output(run, "Electricity:Facility", by = "hour"),
               class = "bayesbem_error_eplus_output")
})

test_that("the errors file is parsed with continuation lines", {
  err <- withr::local_tempfile()
  writeLines(c("Program Version,EnergyPlus, Version 25.2.0",
               "   ** Warning ** first warning",
               "   **   ~~~   ** its detail",
               "   ** Severe  ** a severe one",
               "   **  Fatal  ** stop",
               "   ...Summary of Errors that led to program termination:"), err)
  errors <- bayesbem:::read_err(err)
  expect_equal(errors$level, c("Warning", "Severe", "Fatal"))
  expect_equal(errors$message, c("first warning its detail", "a severe one", "stop"))
})

test_that("fields EnergyPlus does not know, bad values and time limits are classed errors", {
  skip_if_no_eplus()
  model <- seb_model()
  typo <- eplus_set(model, "Lights", "AllLights", `Watts per Flor Area` = 3)
  expect_snapshot(eplus_run(typo, shipped_epw(2013)), error = TRUE)
  bad <- eplus_set(model, "Material", "Stuco", Conductivity = -1)
  expect_snapshot(eplus_run(bad, shipped_epw(2013)), error = TRUE)
  err <- expect_error(eplus_run(model, shipped_epw(2013), timeout = 1),
                      class = "bayesbem_error_eplus_run")
  expect_match(conditionMessage(err), "time limit of 1 s")
  expect_error(eplus_run(model, "no-such.epw"), class = "bayesbem_error_file")
})

test_that("a model with HVACTemplate objects is expanded by ExpandObjects and runs", {
  idf <- withr::local_tempfile(fileext = ".idf")
  writeLines(c(readLines(example_model_path("1ZoneUncontrolled_25_2.idf")),
               "HVACTemplate:Thermostat, Constant Setpoints, , 20, , 24;",
               "HVACTemplate:Zone:IdealLoadsAirSystem, ZONE ONE, Constant Setpoints;"), idf)
  model <- eplus_model(idf)
  expect_true("ZoneHVAC:IdealLoadsAirSystem" %in% names(model$json))
  model <- eplus_add(model, "Output:Variable", key_value = "ZONE ONE",
                     variable_name = "Zone Mean Air Temperature", reporting_frequency = "Daily")
  run <- eplus_run(model, shipped_epw(2013))
  temp <- eplus_output(run, "Zone Mean Air Temperature", key = "ZONE ONE")
  expect_equal(nrow(temp), 365)
  # ideal loads hold the zone between the setpoints
  expect_true(all(temp$value > 19.9 & temp$value < 24.1))
  expect_error(eplus_add(model, "HVACTemplate:Thermostat", "T"), class = "bayesbem_error_eplus_model")
})

test_that("a weather file holding 29 February runs as a leap year, its model untouched", {
  dir <- withr::local_tempdir()
  template <- shipped_epw(2013)
  records <- c("2012,2,28,1,60,fields", "2012,2,29,1,60,fields", "2012,3,1,1,60,fields")
  leap <- epw_with_records(template, records)
  model <- list(json = list(RunPeriod = list(
    `Run Period 1` = list(begin_month = 1, begin_day_of_month = 1),
    `Run Period 2` = list(begin_month = 1, begin_year = 2011))))
  out <- leap_day_setup(model, leap, dir)
  expect_match(readLines(out$weather, n = 5)[5], "^HOLIDAYS/DAYLIGHT SAVINGS,Yes,")
  expect_equal(readLines(out$weather)[-5], readLines(leap)[-5])
  expect_equal(out$model$json$RunPeriod$`Run Period 1`$begin_year, 2012)
  expect_equal(out$model$json$RunPeriod$`Run Period 1`$end_year, 2012)
  # a run period with a year of its own is the modeller's choice
  expect_equal(out$model$json$RunPeriod$`Run Period 2`, model$json$RunPeriod$`Run Period 2`)
  # a file without the day is used as it is
  plain <- epw_with_records(template, records[-2])
  expect_identical(leap_day_setup(model, plain, dir), list(model = model, weather = plain))
})

test_that("measured weather of a leap year is simulated on every day it holds", {
  skip_if_no_eplus()
  epw <- shipped_epw(2012)  # 8784 hours under a header that says there is no leap day
  expect_match(readLines(epw, n = 5)[5], "^HOLIDAYS/DAYLIGHT SAVINGS,No,")
  run <- eplus_run(with_output(seb_model(), "Electricity:Facility"), epw)
  daily <- eplus_output(run, "Electricity:Facility")
  expect_equal(nrow(daily), 366)
  expect_equal(sum(daily$month == 2), 29)
  sim <- eplus_simulator(weather = epw)
  runs <- simulate_design(sim, data.frame(equipment_power_density = 15))
  expect_equal(nrow(runs), 12)
  expect_length(attr(runs, "failed")$run, 0)
  # a model dated 2013 runs on the 2012 weather in 2012, saying so
  dated <- seb_model()
  dated$json$RunPeriod[[1]]$begin_year <- 2013
  dated$json$RunPeriod[[1]]$end_year <- 2013
  expect_message(run <- eplus_run(with_output(dated, "Electricity:Facility"), epw),
                 "dated 2013", class = "bayesbem_message_run_period")
  expect_equal(eplus_output(run, "Electricity:Facility")$value, daily$value, tolerance = 1e-9)
  expect_message(dated_sim <- eplus_simulator(dated, weather = epw),
                 class = "bayesbem_message_run_period")
  expect_equal(simulate_design(dated_sim, data.frame(equipment_power_density = 15))$eta,
               runs$eta, tolerance = 1e-9)
})

test_that("EnergyPlus by hour: the hourly meter, each hour stamped by its end as the weather's", {
  skip_if_no_eplus()
  hourly <- simulate_design(seb_eplus(by = "hour"), data.frame(equipment_power_density = 15))
  daily <- simulate_design(seb_eplus(by = "day"), data.frame(equipment_power_density = 15))
  expect_equal(nrow(hourly), 8760)
  expect_named(hourly[2:6], c("temp", "rh", "solar", "weekday", "daytype_hour"))
  w <- epw_weather(shipped_epw(2013), by = "hour")
  expect_equal(hourly$temp, w$temp)
  expect_equal(as.vector(tapply(hourly$eta, w$date, sum)), daily$eta, tolerance = 1e-9)
})
