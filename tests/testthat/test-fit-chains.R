test_that("chains run one per process give rstan's own multi-chain draws", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  stan_data <- bayesbem:::koh_stan_data(d, koh_priors(), NULL, "grid")
  reference <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh_grid, data = stan_data, chains = 2, iter = 150,
                    seed = 5, refresh = 0, control = list(adapt_delta = 0.9), cores = 1)
  )
  fit <- suppressWarnings(calibrate(d, chains = 2, iter = 150, seed = 5, cores = 2),
                          classes = "bayesbem_warning_convergence")
  expect_equal(as.array(fit$stanfit), as.array(reference))
})

test_that("rstan's diagnostic warnings are told by the function that raised them", {
  skip_on_cran()
  short <- suppressWarnings(
    rstan::sampling(bayesbem:::stanmodels$koh_grid,
                    data = bayesbem:::koh_stan_data(koh_data(seb_field, seb_sim), koh_priors(),
                                                    NULL, "grid"),
                    chains = 2, iter = 30, seed = 1, refresh = 0)
  )
  told <- logical()
  withCallingHandlers({
    rstan:::throw_sampler_warnings(short)
    warning("something else")
  }, warning = function(w) {
    told[conditionMessage(w)] <<- bayesbem:::from_rstan_diagnostics()
    invokeRestart("muffleWarning")
  })
  expect_gt(length(told), 1)
  expect_true(all(told[names(told) != "something else"]))
  expect_false(told[["something else"]])
})

test_that("progress is read from Stan's iteration lines", {
  logs <- c(tempfile(), tempfile(), tempfile())
  writeLines(c("Chain 1: Iteration:   1 / 400 [  0%]  (Warmup)",
               "Chain 1: Iteration: 120 / 400 [ 30%]  (Warmup)"), logs[1])
  writeLines(c("Chain 2: Iteration: 400 / 400 [100%]  (Sampling)", "Chain 2: ",
               "Chain 2:  Elapsed Time: 0.1 seconds (Warm-up)"), logs[2])
  expect_equal(bayesbem:::chain_progress(logs, 400), c(120, 400, 0))
})

test_that("a chain whose process fails is a classed error", {
  results <- list(list(fit = NULL, warnings = list()), bayesbem:::try_error("out of memory"))
  expect_error(bayesbem:::collect_chains(results, identity, NULL), "out of memory",
               class = "bayesbem_error_sampling")
})

test_that("a list of starting values gives each chain its own", {
  skip_on_cran()
  starts <- list(list(tf = c(0.2, 0.2, 0.2)), list(tf = c(0.8, 0.8, 0.8)))
  fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 2, iter = 20, seed = 1,
                                    init = starts),
                          classes = "bayesbem_warning_convergence")
  expect_equal(lapply(fit$stanfit@inits, function(i) as.vector(i$tf)),
               list(rep(0.2, 3), rep(0.8, 3)))
})
