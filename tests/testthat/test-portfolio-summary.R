# A portfolio's records as calibrate_portfolio() writes them, built by hand.
hand_portfolio <- function() {
  draws <- list(a = 100 + seq(-9.5, 9.5), b = 200 + 2 * seq(9.5, -9.5))
  record <- function(id, saved, fsu) {
    list(id = id, status = "done", converged = TRUE, rhat = 1.001, cvrmse = 5, nmbe = 0.1,
         sufficiency = NA_real_, verdict = "consistent", savings_draws = saved,
         baseline = 1000, fsu_guideline14 = fsu, guideline14_df = 11, warnings = character(),
         seconds = 10)
  }
  records <- list(a = record("a", draws$a, 0.1), b = record("b", draws$b, 0.05),
                  c = list(id = "c", status = "refused", error = "too {large}\nmore",
                           error_class = "bayesbem_error_too_large"))
  structure(list(dir = tempdir(), records = records), class = "bayesbem_portfolio")
}

test_that("the total sums the buildings' draws draw by draw, beside Guideline 14's aggregate", {
  s <- summary(hand_portfolio())
  total <- 100 + seq(-9.5, 9.5) + 200 + 2 * seq(9.5, -9.5)
  expect_equal(s$total$savings, mean(total))
  # of 20 draws, [min, max] holds a new one with probability 19/21 >= 0.9
  # and the next order statistics' 17/21 < 0.9
  expect_equal(c(s$total$lower, s$total$upper), range(total))
  # Guideline 14: absolute uncertainties in quadrature over the total
  expect_equal(s$total$fsu_guideline14, sqrt((0.1 * 100)^2 + (0.05 * 200)^2) / 300)
  expect_equal(s$buildings$status, c("done", "done", "refused"))
  expect_equal(s$buildings$savings[1:2], c(100, 200))
  expect_true(is.na(s$buildings$savings[3]))
  # at another level Guideline 14's Student quantile is rescaled
  s80 <- summary(hand_portfolio(), level = 0.8)
  expect_equal(s80$buildings$fsu_guideline14[1], 0.1 * qt(0.9, 11) / qt(0.95, 11))
})

test_that("a portfolio prints its counts, total and errors, and plots from its data", {
  p <- hand_portfolio()
  expect_output(print(p), "2 done, 0 failed, 1 refused, 0 missing")
  expect_output(print(p), "c \\(refused\\): too \\{large\\}")
  d <- plot_portfolio_data(p)
  expect_equal(d$id, c("a", "b", "total"))
  expect_equal(d$savings, c(100, 200, 300))
  expect_s3_class(plot_portfolio(p), "ggplot")
  p$records <- p$records["c"]
  expect_error(plot_portfolio_data(p), class = "bayesbem_error_argument")
  expect_error(plot_portfolio_data(list()), class = "bayesbem_error_argument")
  expect_error(summary(p, levle = 0.8), class = "rlib_error_dots_nonempty")
})

test_that("draws of different lengths are not summed", {
  p <- hand_portfolio()
  p$records$b$savings_draws <- p$records$b$savings_draws[1:19]
  expect_error(summary(p), "different numbers of draws", class = "bayesbem_error_argument")
})
