# drawn from the shipped seb_fit and the embedded model with a fixed seed:
# the same on every machine
test_that("plot_emulator_check() draws the emulator's intervals and the simulator's outputs", {
  withr::local_seed(4)
  check <- validate_emulator(seb_fit, linear_seb_simulator(), ndraws = 4)
  d <- plot_emulator_check_data(check)
  expect_equal(nrow(d), nrow(check$table))
  expect_true(all(abs(d$position - d$period) <= 0.3 + 1e-12))
  expect_identical(plot(check)$data, d)
  expect_error(plot_emulator_check_data(seb_fit), class = "bayesbem_error_argument")
  skip_if_not_installed("vdiffr")
  vdiffr::expect_doppelganger("emulator-check", plot_emulator_check(check))
})
