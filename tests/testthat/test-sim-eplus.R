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
  annual <- tapply(out$eta, out$equipment_power_density, sum)
  # the base model's annual electricity (models/README.md: 25,085 kWh)
  expect_equal(annual[["21.9"]], 25085, tolerance = 1e-3)
  expect_lt(annual[["10"]], annual[["21.9"]] - 3000)
  expect_equal(out[1:12, c("temp", "rh")], seb_field[c("temp", "rh")], ignore_attr = TRUE)
})

test_that("the parameter map is checked against the model and the IDD", {
  skip_if_no_eplus()
  map <- eplus_parameter_map()
  map$object_name[1] <- "No Such Schedule"
  map$field[5] <- "Fan Efficiency"
  expect_snapshot(eplus_simulator(weather = shipped_epw(2013), map = map), error = TRUE)
  map <- eplus_parameter_map()
  map$apply[1] <- "add"
  expect_error(eplus_simulator(weather = shipped_epw(2013), map = map),
               class = "bayesbem_error_parameters")
})

test_that("wrong IDF versions and failed runs get classed errors", {
  skip_if_no_eplus()
  model <- bayesbem:::read_idf(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
  classes <- vapply(model, `[`, character(1), 1)
  model[[which(classes == "Version")]][2] <- "23.1"
  old <- withr::local_tempfile(fileext = ".idf")
  bayesbem:::write_idf(model, old)
  expect_error(eplus_simulator(old, weather = shipped_epw(2013)),
               class = "bayesbem_error_eplus_version")
  expect_snapshot(eplus_simulator(old, weather = shipped_epw(2013)), error = TRUE,
                  transform = function(x) sub("file[0-9a-f]+\\.idf", "<file>.idf", x))
  sim <- seb_eplus()
  base <- stats::setNames(as.list(sim$parameters$initial), sim$parameters$parameter)
  expect_error(sim$fun(utils::modifyList(base, list(fan_total_efficiency = -1)), sim$x),
               class = "bayesbem_error_eplus_run")
})

test_that("Morris screening, a Latin hypercube and calibration run on EnergyPlus", {
  skip_if_no_eplus()
  skip_if_not_installed("sensitivity")
  sim <- seb_eplus()
  withr::local_options(future.rng.onMisuse = "ignore")
  future::plan(future::multisession, workers = 2)
  on.exit(future::plan(future::sequential), add = TRUE)
  m <- screen_morris(sim, r = 2, seed = 1)
  expect_equal(nrow(m), 14)
  top <- m$parameter[m$rank <= 3]
  # plug loads dominate the electricity of this building
  expect_true("equipment_power_density" %in% top)
  design <- design_lhs(sim$parameters[sim$parameters$parameter %in% top, ], n = 10, seed = 2)
  table <- simulate_design(sim, design)
  expect_equal(nrow(table), 120)
  field <- data.frame(y = seb_field$y, sim$x)
  fit <- suppressWarnings(calibrate(field, table, chains = 1, iter = 300, seed = 3, refresh = 0),
                          classes = "bayesbem_warning_convergence")
  expect_s3_class(fit, "koh_fit")
  expect_equal(fit$settings$structure, "grid")
  expect_setequal(summary(fit)$parameters$variable, top)
})
