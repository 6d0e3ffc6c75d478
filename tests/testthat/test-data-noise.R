# The noise of periods of different lengths (R/data-noise.R); the programs'
# densities with each row's noise are checked against the references in
# test-fit.R, test-fit-basis.R and test-predict.R (random_grid_data(days = TRUE)).

test_that("a period's total of independent daily errors has variance proportional to its days", {
  withr::local_seed(1)
  days <- c(7, 26, 30, 34, 61)
  totals <- vapply(days, function(k) colSums(matrix(stats::rnorm(k * 4000, sd = 2), k)),
                   numeric(4000))
  x <- data.frame(days = days)
  w <- bayesbem:::period_weights(x)
  expect_equal(w, days / mean(days))
  # var(total_i) / w_i is one number, the variance of a period of the mean length
  per_weight <- apply(totals, 2, stats::var) / w
  expect_equal(per_weight, rep(4 * mean(days), length(days)), tolerance = 0.1)
})

test_that("koh_data() weighs each period's noise by its days, on the field's mean", {
  withr::local_seed(2)
  d <- random_grid_data(n = 6, extra = 2, days = TRUE)
  days <- d$field$days
  expect_equal(d$scaling$days, mean(days))
  expect_equal(bayesbem:::noise_weights(d), days / mean(days))
  # new periods on the same reference
  expect_equal(bayesbem:::noise_weights(d, data.frame(days = c(15, 60))), c(15, 60) / mean(days))
  expect_match(paste(utils::capture.output(print(d)), collapse = "\n"), "proportional to each period's")
  priors <- koh_priors()
  expect_equal(as.vector(bayesbem:::koh_stan_data(d, priors, structure = "grid")$noise_weight),
               days / mean(days))
  x_pred <- d$xf[1:2, , drop = FALSE]
  dense <- bayesbem:::koh_stan_data(d, priors, x_pred = x_pred)
  expect_equal(as.vector(dense$noise_weight), days / mean(days))
  expect_equal(as.vector(dense$noise_weight_pred), days[1:2] / mean(days))
  # without `days` every weight is 1 (the paper's model)
  plain <- koh_data(seb_field, seb_sim)
  expect_null(plain$scaling$days)
  expect_equal(bayesbem:::noise_weights(plain), rep(1, 12))
})

test_that("each output's periods weigh its own noise", {
  withr::local_seed(3)
  r <- random_outputs_data()
  days <- sample(20:40, nrow(unique(r$sim[c("a", "b")])), replace = TRUE)
  key <- function(t) paste(t$a, t$b)
  lookup <- stats::setNames(days, unique(key(r$sim)))
  r$field$days <- unname(lookup[key(r$field)])
  r$sim$days <- unname(lookup[key(r$sim)])
  d <- koh_data(r$field, r$sim)
  sd <- bayesbem:::stage2_stan_data(d, koh_priors(emulator_mean = "zero"))
  expected <- unlist(lapply(d$outputs, function(o) o$field$days / mean(o$field$days)))
  expect_equal(as.vector(sd$noise_weight), unname(expected))
})

test_that("noise draws and simulated bills grow with the period's days", {
  withr::local_seed(4)
  fit <- list(data = list(scaling = list(y_scale = 2, days = 30)))
  draws <- lapply(c(1, 4), function(l) list(lambda_e = l))
  e <- bayesbem:::noise_draws(fit, draws[rep(1:2, 20000)], data.frame(days = c(15, 60)))
  # sd = y_scale * sqrt(w / lambda_e), draw by draw
  expect_equal(apply(e[c(TRUE, FALSE), ], 2, stats::sd), 2 * sqrt(c(0.5, 2)), tolerance = 0.03)
  expect_equal(apply(e[c(FALSE, TRUE), ], 2, stats::sd), 2 * sqrt(c(0.5, 2) / 4), tolerance = 0.03)

  weather <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
  bills <- data.frame(start = as.Date(c("2013-01-01", "2013-01-08", "2013-03-01")),
                      end = as.Date(c("2013-01-07", "2013-02-28", "2013-03-30")))
  sim <- bem_simulator(weather, periods = bills)
  field <- simulate_field(sim, list(equipment_power_density = 15), noise_sd = 10, seed = 5)
  noise <- field$y - attr(field, "simulated")
  w <- sim$x$days / mean(sim$x$days)
  expect_equal(noise / sqrt(w), withr::with_seed(5, stats::rnorm(3, sd = 10)))
})

test_that("AR(1) segments break at gaps and steps back", {
  t0 <- as.POSIXct("2013-03-09 22:00", tz = "UTC")
  times <- t0 + 3600 * c(0, 1, 2, 4, 5, 5, 6, 3)
  expect_equal(bayesbem:::noise_segments(times), c(1, 1, 1, 2, 2, 3, 3, 4))
  expect_equal(bayesbem:::noise_segments(as.Date("2013-01-01") + c(0:3, 10:11)),
               c(1, 1, 1, 1, 2, 2))
  expect_equal(bayesbem:::noise_segments(t0), 1)
})

test_that("months are read in the times' own zone", {
  utc <- as.POSIXct(c("2019-09-30 23:30", "2019-10-01 00:30"), tz = "UTC")
  expect_equal(bayesbem:::period_months(utc), c("2019-09", "2019-10"))
  attr(utc, "tzone") <- "Europe/London"
  expect_equal(bayesbem:::period_months(utc), c("2019-10", "2019-10"))
  expect_equal(bayesbem:::period_months(as.Date(c("2013-01-31", "2013-02-01"))),
               c("2013-01", "2013-02"))
  m <- bayesbem:::shift_columns(c("b", "a", "b"))
  expect_equal(colnames(m), c("a", "b"))
  expect_equal(unname(m), cbind(c(0, 1, 0), c(1, 0, 1)))
})
