test_that("simulate_design() returns the [eta, x, t] table calibrate() takes", {
  sim <- bem_simulator(shipped_epw(2013))
  design <- design_lhs(bem_parameters()[c(3, 12, 14), ], n = 6, seed = 2)
  table <- simulate_design(sim, design)
  expect_named(table, c("eta", "temp", "rh", "solar", "fan_total_efficiency",
                        "equipment_power_density", "infiltration_per_exterior_area"))
  expect_equal(nrow(table), 6 * 12)
  expect_equal(table$equipment_power_density[13:24], rep(design$equipment_power_density[2], 12))
  expect_equal(table$temp[13:24], seb_field$temp, tolerance = 1e-12)
  p <- utils::modifyList(stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter),
                         as.list(design[2, ]))
  expect_equal(table$eta[13:24], bem_monthly(p, epw_monthly(shipped_epw(2013)))$electricity)
  expect_equal(nrow(attr(table, "failed")), 0)
  d <- koh_data(seb_field, table)
  expect_equal(c(d$n, d$m, d$p, d$q), c(12, 72, 3, 3))
})

test_that("failed runs are reported by row, kept out, and rerun alone from the cache", {
  calls <- new.env()
  calls$n <- 0
  flaky <- simulator(function(params, x) {
    calls$n <- calls$n + 1
    if (params$a > 1.5 && is.null(calls$fixed)) stop("solver diverged")
    params$a * x$temp
  }, x = data.frame(temp = 1:3),
  parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  cache <- tempfile("cache")
  design <- data.frame(a = c(0.5, 1.8, 1.0, 1.9))
  expect_warning(first <- simulate_design(flaky, design, cache_dir = cache),
                 class = "bayesbem_warning_simulation")
  expect_equal(attr(first, "failed")$run, c(2, 4))
  expect_match(attr(first, "failed")$error, "solver diverged")
  expect_equal(nrow(first), 2 * 3)
  expect_equal(calls$n, 4)
  calls$fixed <- TRUE
  second <- simulate_design(flaky, design, cache_dir = cache)
  expect_equal(calls$n, 6)
  expect_equal(nrow(attr(second, "failed")), 0)
  expect_equal(second$eta, rep(design$a, each = 3) * rep(1:3, 4))
})

test_that("a simulator returning the wrong length is a failed run", {
  bad <- simulator(function(params, x) 1, x = data.frame(temp = 1:3),
                   parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  expect_warning(out <- simulate_design(bad, data.frame(a = 1)), class = "bayesbem_warning_simulation")
  expect_match(attr(out, "failed")$error, "length 1, not 3")
})

test_that("runs go through future plans", {
  skip_on_cran()
  sim <- bem_simulator(shipped_epw(2013))
  design <- design_lhs(bem_parameters()[12:13, ], n = 4, seed = 5)
  sequential <- simulate_design(sim, design)
  old <- future::plan(future::multisession, workers = 2)
  on.exit(future::plan(old), add = TRUE)
  parallel <- simulate_design(sim, design)
  expect_equal(parallel, sequential)
})

test_that("runs go to a cluster through a future cluster plan, sharing the cache", {
  skip_on_cran()
  # the route to a cluster: a PSOCK cluster object here, the nodes of a
  # scheduler (future.batchtools) or of other machines elsewhere
  sim <- bem_simulator(shipped_epw(2013))
  design <- design_lhs(bem_parameters()[12:13, ], n = 4, seed = 6)
  sequential <- simulate_design(sim, design)
  cl <- parallel::makePSOCKcluster(2)
  on.exit(parallel::stopCluster(cl), add = TRUE)
  old <- future::plan(future::cluster, workers = cl)
  on.exit(future::plan(old), add = TRUE)
  cache <- withr::local_tempdir()
  remote <- simulate_design(sim, design, cache_dir = cache)
  expect_equal(remote, sequential)
  expect_length(list.files(cache), 4)
  # the workers ran in other processes
  pids <- future.apply::future_sapply(1:2, function(i) Sys.getpid())
  expect_false(Sys.getpid() %in% pids)
})

test_that("the cache key covers everything that changes a simulator's output", {
  cache <- tempfile("cache")
  design <- data.frame(equipment_power_density = c(10, 20))
  epw <- epw_monthly(shipped_epw(2013))
  small <- simulate_design(bem_simulator(epw), design, cache_dir = cache)
  big <- simulate_design(bem_simulator(epw, building = bem_building(floor_area = 200)), design,
                         cache_dir = cache)
  fresh <- simulate_design(bem_simulator(epw, building = bem_building(floor_area = 200)), design)
  expect_equal(big$eta, fresh$eta)
  expect_false(isTRUE(all.equal(big$eta, small$eta)))
  gas <- simulate_design(bem_simulator(epw, output = "gas"), design, cache_dir = cache)
  expect_false(isTRUE(all.equal(gas$eta, small$eta)))
  # custom simulators of the same name that differ in a captured value or a global
  make <- function(k) {
    simulator(function(params, x) k * params$a * x$temp, x = data.frame(temp = 1:3),
              parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  }
  one <- simulate_design(make(1), data.frame(a = 1), cache_dir = cache)
  two <- simulate_design(make(2), data.frame(a = 1), cache_dir = cache)
  expect_equal(two$eta, 2 * one$eta)
  scale_factor <- 3
  scaled <- simulator(function(params, x) scale_factor * x$temp, x = data.frame(temp = 1:3),
                      parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  expect_equal(simulate_design(scaled, data.frame(a = 1), cache_dir = cache)$eta, c(3, 6, 9))
  scale_factor <- 4
  expect_equal(simulate_design(scaled, data.frame(a = 1), cache_dir = cache)$eta, c(4, 8, 12))
  # and an explicit key for what the code cannot show (e.g. a file's contents)
  keyed <- function(version) {
    simulator(function(params, x) x$temp, x = data.frame(temp = 1:3), key = version,
              parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  }
  simulate_design(keyed("v1"), data.frame(a = 1), cache_dir = cache)
  n_files <- length(list.files(cache))
  simulate_design(keyed("v2"), data.frame(a = 1), cache_dir = cache)
  expect_equal(length(list.files(cache)), n_files + 1)
})

test_that("simulate_design() leaves the session's random number generator as it was", {
  sim <- bem_simulator(shipped_epw(2013))
  withr::local_seed(1)
  rm(".Random.seed", envir = globalenv())
  kind <- RNGkind()
  simulate_design(sim, data.frame(equipment_power_density = 10))
  expect_equal(RNGkind(), kind)
  expect_false(exists(".Random.seed", envir = globalenv()))
})

test_that("a simulator of several outputs gives the long table, one run per setting", {
  calls <- 0
  two <- simulator(function(params, x) {
    calls <<- calls + 1
    data.frame(elec = params$a * x$temp, gas = params$a + x$temp)
  }, x = data.frame(temp = c(1, 2, 3)),
  parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  out <- simulate_design(two, data.frame(a = c(0.5, 1.5)))
  expect_equal(calls, 2)
  expect_named(out, c("output", "eta", "temp", "a"))
  expect_equal(out$output, rep(rep(c("elec", "gas"), each = 3), 2))
  expect_equal(out$eta, c(0.5 * 1:3, 0.5 + 1:3, 1.5 * 1:3, 1.5 + 1:3))
  # a run whose outputs miss a row or a name fails alone
  short <- simulator(function(params, x) data.frame(elec = 1:2, gas = 1:2), x = data.frame(temp = 1:3),
                     parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  expect_warning(out <- simulate_design(short, data.frame(a = 1)), class = "bayesbem_warning_simulation")
  expect_match(attr(out, "failed")$error, "2 rows, not 3")
  # runs that disagree on their outputs are an error
  changing <- simulator(function(params, x) {
    if (params$a > 1) data.frame(elec = x$temp) else data.frame(gas = x$temp)
  }, x = data.frame(temp = 1:3), parameters = data.frame(parameter = "a", initial = 1, min = 0, max = 2))
  expect_error(simulate_design(changing, data.frame(a = c(0.5, 1.5))),
               class = "bayesbem_error_simulation")
})
