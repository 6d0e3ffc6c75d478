# The fit object's draws, built without sampling.

test_that("a stage-2 fit's draws hold each output's fixed emulator, named as a joint fit's", {
  r <- random_outputs_data()
  d <- koh_data(r$field, r$sim)
  emulators <- list(elec = list(beta_eta = 1:5, lambda_eta = 2, b = c(0.1, 0.2)),
                    gas = list(beta_eta = 6:10, lambda_eta = 3, b = c(0.3, 0.4)))
  sampled <- posterior::draws_array(`tf[1]` = matrix(stats::runif(8), 4),
                                    `lambda_e[2]` = matrix(1, 4, 2), lp__ = matrix(-1, 4, 2))
  draws <- bayesbem:::with_fixed_emulator(sampled, d, emulators)
  expect_equal(posterior::variables(draws),
               c("tf[1]", "lambda_e[2]", sprintf("beta_eta[%d]", 1:10), "lambda_eta[1]",
                 "lambda_eta[2]", sprintf("b[%d]", 1:4), "lp__"))
  expect_equal(posterior::ndraws(draws), 8)
  expect_true(all(posterior::extract_variable(draws, "beta_eta[7]") == 7))
  expect_true(all(posterior::extract_variable(draws, "lambda_eta[2]") == 3))
  # the sampled draws are untouched
  expect_equal(posterior::extract_variable(draws, "tf[1]"),
               posterior::extract_variable(sampled, "tf[1]"))
  # each output's elements then take its name
  named <- bayesbem:::output_draw_names(posterior::variables(draws), d, emulators)
  expect_true(all(c("gas:lambda_eta", "elec:lambda_eta", "gas:beta_eta[1]", "gas:b[2]",
                    "gas:lambda_e") %in% named))
})

test_that("a joint fit's precisions, vectors of one in Stan, are named as numbers", {
  d <- koh_data(seb_field, seb_sim)
  variables <- c("tf[1]", "rho_delta[1]", "lambda_eta[1]", "lambda_delta[1]", "lambda_e[1]",
                 "b[1]", "beta_eta[1]", "lp__")
  expect_equal(bayesbem:::output_draw_names(variables, d, NULL),
               c("tf[1]", "rho_delta[1]", "lambda_eta", "lambda_delta", "lambda_e", "b[1]",
                 "beta_eta[1]", "lp__"))
})

test_that("a fit's AR(1) segments are the ones calibrate() resolved, read by one predicate", {
  case <- ar1_basis_case()
  d <- case$data
  ar1 <- list(noise_correlation = "ar1", segments = list(c(1L, 1L, 2L)))
  fit <- bayesbem:::new_bayesbem_fit(NULL, NULL, NULL, d, koh_priors(), ar1)
  expect_true(bayesbem:::is_ar1(fit$settings))
  expect_equal(bayesbem:::fit_segments(fit), c(1L, 1L, 2L))
  # a fit made before they were kept finds them from its data
  fit$settings$segments <- NULL
  expect_equal(bayesbem:::fit_segments(fit), case$segments)
  white <- bayesbem:::new_bayesbem_fit(NULL, NULL, NULL, d, koh_priors(),
                                       list(noise_correlation = "none"))
  expect_false(bayesbem:::is_ar1(white$settings))
  expect_null(bayesbem:::fit_segments(white))
})
