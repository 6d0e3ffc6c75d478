test_that("optimised BLAS libraries are told from the reference one by name", {
  expect_true(bayesbem:::optimised_blas("/usr/lib/x86_64-linux-gnu/openblas-pthread/libblas.so.3"))
  expect_true(bayesbem:::optimised_blas("/opt/intel/oneapi/mkl/latest/lib/libmkl_rt.so.2"))
  expect_true(bayesbem:::optimised_blas("/usr/lib/x86_64-linux-gnu/blis-openmp/libblas.so.3"))
  expect_true(bayesbem:::optimised_blas(
    "/System/Library/Frameworks/Accelerate.framework/Versions/A/Frameworks/vecLib.framework/Versions/A/libBLAS.dylib"))
  expect_false(bayesbem:::optimised_blas("/usr/lib/x86_64-linux-gnu/blas/libblas.so.3.11.0"))
  expect_false(bayesbem:::optimised_blas("/usr/lib/R/lib/libRblas.so"))
  expect_false(bayesbem:::optimised_blas(""))
})

test_that("the option bayesbem.lapack chooses the library, and the data say so", {
  d <- koh_data(seb_field, seb_sim)
  emulator <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1, b = numeric(1 + d$p + d$q))
  for (choice in c(TRUE, FALSE)) {
    withr::local_options(bayesbem.lapack = choice)
    expect_identical(bayesbem:::use_lapack(), choice)
    expect_identical(bayesbem:::koh_stan_data(d, koh_priors(), structure = "grid")$lapack,
                     as.integer(choice))
    expect_identical(bayesbem:::modular_stan_data(d, koh_priors(), emulator)$lapack,
                     as.integer(choice))
  }
  withr::local_options(bayesbem.lapack = NULL)
  expect_identical(bayesbem:::use_lapack(), bayesbem:::optimised_blas(extSoftVersion()[["BLAS"]]))
})

test_that("a wrong bayesbem.lapack is a classed error before any sampling", {
  withr::local_options(bayesbem.lapack = "yes")
  expect_error(calibrate(seb_field, seb_sim), class = "bayesbem_error_option")
  expect_snapshot(calibrate(seb_field, seb_sim), error = TRUE)
})

test_that("a large fit on Eigen says once that an optimised BLAS would be faster", {
  withr::local_options(bayesbem.lapack = NULL)
  rlang::reset_message_verbosity("bayesbem_blas")
  withr::defer(rlang::reset_message_verbosity("bayesbem_blas"))
  expect_silent(bayesbem:::inform_blas(365, lapack = TRUE, field_density = TRUE))
  expect_silent(bayesbem:::inform_blas(120, lapack = FALSE, field_density = TRUE))
  expect_silent(bayesbem:::inform_blas(365, lapack = FALSE, field_density = FALSE))
  withr::with_options(list(bayesbem.lapack = FALSE),
                      expect_silent(bayesbem:::inform_blas(365, lapack = FALSE, field_density = TRUE)))
  expect_message(bayesbem:::inform_blas(365, lapack = FALSE, field_density = TRUE),
                 "365 x 365", class = "bayesbem_message_blas")
  expect_silent(bayesbem:::inform_blas(365, lapack = FALSE, field_density = TRUE))
})
