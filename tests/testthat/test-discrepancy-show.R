test_that("discrepancy() gives delta and the simulator residual at every field point", {
  skip_on_cran()
  fit <- shared_fit()
  withr::local_seed(11)
  d <- discrepancy(fit, ndraws = 300)
  expect_s3_class(d, "bayesbem_discrepancy")
  expect_equal(nrow(d), 12)
  expect_equal(d$obs, seb_field$y)
  expect_true(all(d$delta_lower <= d$delta_mean & d$delta_mean <= d$delta_upper))
  expect_equal(d$flag, d$band_lower > 0 | d$band_upper < 0)
  # the simultaneous band is wider than every pointwise interval
  expect_true(all(d$band_lower <= d$residual_lower & d$band_upper >= d$residual_upper))
  expect_gt(attr(d, "critical"), stats::qnorm(0.95))
  expect_equal(d$delta_share, 100 * d$delta_mean / d$obs)
  # the residual is y - eta for the same posterior draws of eta
  draws <- withr::with_seed(11, bayesbem:::predict_draws(fit, seb_field[2:4], ndraws = 300))
  expect_equal(d$residual_mean, seb_field$y - colMeans(draws$eta))
  expect_equal(d$delta_mean, colMeans(draws$delta))
  expect_type(attr(d, "verdict"), "character")
  expect_output(print(d), "The simulator is")
})

test_that("the verdict says consistent, or names the points and the sign", {
  base <- data.frame(point = 1:4, obs = 100, residual_mean = c(1, -1, 20, -15),
                     residual_share = c(1, -1, 20, -15), flag = FALSE)
  expect_match(bayesbem:::discrepancy_verdict(base, 0.9), "consistent with the data")
  flagged <- base
  flagged$flag <- c(FALSE, FALSE, TRUE, TRUE)
  verdict <- bayesbem:::discrepancy_verdict(flagged, 0.9)
  expect_match(verdict, "wrong at 2 of 4 points")
  expect_match(verdict, "under-predicts at point 3 \\(by 20%")
  expect_match(verdict, "over-predicts at point 4 \\(by 15%")
})

test_that("the verdict on thousands of points names a few", {
  hours <- data.frame(point = 1:6550, obs = 100, residual_mean = 50, residual_share = 50,
                      flag = TRUE)
  verdict <- bayesbem:::discrepancy_verdict(hours, 0.9)
  expect_match(verdict, "under-predicts at 6550 points, the first 1, 2, 3, 4, 5 \\(by 50%")
  expect_lt(nchar(verdict), 200)
})

test_that("the simultaneous band holds its level over all points at once", {
  # 20 independent standard normal points: a pointwise 90 % interval misses
  # some point in most draws, the band in 10 % of them
  withr::local_seed(8)
  draws <- matrix(rnorm(4000 * 20), 4000, 20)
  band <- bayesbem:::simultaneous_band(draws, 0.9)
  expected <- qnorm((1 + 0.9^(1 / 20)) / 2)  # Sidak: P(max |z| < c) = 0.9
  expect_equal(band$critical, expected, tolerance = 0.02)
  fresh <- matrix(rnorm(4000 * 20), 4000, 20)
  outside <- apply(fresh, 1, function(z) any(z < band$lower | z > band$upper))
  expect_equal(mean(outside), 0.1, tolerance = 0.15)
})

test_that("shares stay finite where the output is near zero", {
  obs <- c(1000, 800, 0, 5, 900)
  scale <- bayesbem:::share_scale(obs)
  expect_equal(scale, c(1000, 800, 0.1 * mean(obs), 0.1 * mean(obs), 900))
  expect_true(all(is.finite(100 / scale)))
})

test_that("a fit on several outputs gets each output's discrepancy, with its own band", {
  skip_on_cran()
  both <- on_both_outputs(discrepancy, 3, ndraws = 40)
  d <- both$all
  own <- both$own
  expect_s3_class(d, "bayesbem_discrepancy")
  expect_equal(d$residual_mean[both$electricity], own$residual_mean)
  expect_named(attr(d, "critical"), c("electricity", "gas"))
  expect_match(attr(d, "verdict"), "^electricity: .*\ngas: ")
  pd <- plot_discrepancy_data(d)
  expect_equal(unique(pd$output), c("electricity", "gas"))
  expect_equal(pd$mean[pd$output == "electricity"], plot_discrepancy_data(own)$mean)
  expect_s3_class(plot_discrepancy(d), "ggplot")
  expect_error(discrepancy(both$fit, newdata = seb_field[1:2, ], obs = c(1, 2)),
               class = "bayesbem_error_argument")
})
