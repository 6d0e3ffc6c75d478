test_that("a central interval from n draws is the order statistics that hold a new draw with probability >= level", {
  x <- matrix(c(40:1, 101:140), ncol = 2)
  # 40 draws at 0.9: ranks floor(41 * 0.05) = 2 and 41 - 2 = 39
  expect_equal(column_intervals(x, 0.9), cbind(lower = c(2, 102), upper = c(39, 139)))
  # 19 draws are the fewest for 0.9: the smallest and largest, (19 - 1) / 20 = 0.9
  expect_equal(column_intervals(matrix(19:1), 0.9), cbind(lower = 1, upper = 19))
  # a missing draw is not dropped: its column's interval is unknown
  expect_equal(column_intervals(cbind(c(NA, 1:19), 20:1), 0.9),
               cbind(lower = c(NA, 1), upper = c(NA, 20)))
  # a new draw of the same distribution falls inside (n + 1 - 2k) / (n + 1)
  # of the time (41 - 4) / 41 = 0.902, where the empirical quantiles of 40
  # draws cover about 0.86
  set.seed(1)
  sets <- matrix(stats::rnorm(40 * 20000), nrow = 40)
  new <- stats::rnorm(20000)
  ours <- column_intervals(sets, 0.9)
  theirs <- t(apply(sets, 2, stats::quantile, c(0.05, 0.95)))
  expect_gt(mean(new > ours[, 1] & new < ours[, 2]), 0.895)
  expect_lt(mean(new > theirs[, 1] & new < theirs[, 2]), 0.875)
})

test_that("too few draws for the level give the widest interval, with a warning saying how many would do", {
  x <- matrix(c(5, 1, 3, 2, 4))
  expect_snapshot(bounds <- column_intervals(x, 0.9))
  expect_equal(bounds, cbind(lower = 1, upper = 5))
  expect_warning(covering_rank(18, 0.95), class = "bayesbem_warning_draws")
  expect_no_warning(covering_rank(19, 0.95))
  expect_identical(covering_rank(19, 0.95), 19L)
})

test_that("column summaries give the mean, sd, median and the interval's bounds under quantile names", {
  x <- cbind(a = c(40:1), b = 2 * (1:40))
  s <- summarise_columns(x, data.frame(k = c("a", "b")), 0.9)
  expect_named(s, c("k", "mean", "sd", "q5", "q50", "q95"))
  expect_equal(s$q5, c(2, 4))
  expect_equal(s$q95, c(39, 78))
  expect_equal(s$q50, c(20.5, 41))
  expect_equal(s$sd, apply(x, 2, stats::sd), ignore_attr = TRUE)
})
