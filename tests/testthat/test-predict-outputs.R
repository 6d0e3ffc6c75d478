test_that("predictions of two outputs come from the same draws, and their total adds them", {
  skip_on_cran()
  fit <- two_output_fit()
  newdata <- output_fit(fit, "gas")$data$field[c("temp", "rh", "solar")]
  set.seed(1)
  draws <- predict(fit, newdata, ndraws = 40, summary = FALSE,
                   total = c(electricity = 1, gas = 2))
  expect_named(draws, c("electricity", "gas", "total"))
  expect_equal(draws$total, draws$electricity + 2 * draws$gas)
  # each output's draws are that output's own predictions, draw for draw
  set.seed(1)
  alone <- predict(output_fit(fit, "electricity"), newdata, ndraws = 40, summary = FALSE)
  expect_equal(draws$electricity, alone)
  s <- predict(fit, ndraws = 40)
  expect_equal(names(s)[1], "output")
  expect_equal(as.vector(table(s$output)[c("electricity", "gas")]),
               c(output_fit(fit, 1)$data$n, output_fit(fit, 2)$data$n))
  expect_snapshot(predict(fit, ndraws = 10, total = c(electricity = 1, gas = 1)), error = TRUE)
  expect_snapshot(predict(fit, newdata, ndraws = 10, total = c(water = 1)), error = TRUE)
})
