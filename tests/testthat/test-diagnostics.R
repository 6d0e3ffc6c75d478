test_that("check_convergence() reports every parameter and the sampler", {
  skip_on_cran()
  fit <- shared_fit()
  conv <- check_convergence(fit, warn = FALSE)
  expect_s3_class(conv, "koh_convergence")
  expect_equal(nrow(conv), 15)
  expect_named(conv, c("variable", "rhat", "ess_bulk", "ess_tail", "ok"))
  expect_equal(conv$ok, conv$rhat < 1.01 & conv$ess_bulk >= 200 & conv$ess_tail >= 200)
  sp <- attr(conv, "sampler")
  expect_named(sp, c("divergent", "treedepth_hits", "max_treedepth", "ebfmi"))
  expect_length(sp$ebfmi, 2)
  expect_true(all(sp$ebfmi > 0))
  expect_output(print(conv), "divergent transitions")
})

test_that("a deliberately short run gets a classed convergence warning", {
  skip_on_cran()
  expect_warning(
    calibrate(seb_field, seb_sim, chains = 2, iter = 40, seed = 1, refresh = 0),
    class = "bayesbem_warning_convergence"
  )
})

test_that("a subset of the convergence table prints", {
  conv <- check_convergence(seb_fit, warn = FALSE)
  expect_output(print(conv[, c("variable", "rhat")]), "beta_eta\\[temp\\] +1.856")
  expect_output(print(conv[conv$rhat > 0, ]), "of 15 parameters")
})
