test_that("plot_posteriors_data() gives posterior and prior densities in physical units", {
  skip_on_cran()
  fit <- shared_fit()
  d <- plot_posteriors_data(fit, n_grid = 50)
  expect_named(d, c("parameter", "value", "density", "curve"))
  expect_equal(levels(d$parameter), c("fan_total_efficiency", "equipment_power_density",
                                      "infiltration_per_exterior_area"))
  epd <- d[d$parameter == "equipment_power_density", ]
  expect_equal(range(epd$value), range(seb_sim$equipment_power_density))
  # flat prior: 1 / design range; posterior density integrates to about 1
  expect_equal(unique(epd$density[epd$curve == "prior"]),
               1 / diff(range(seb_sim$equipment_power_density)))
  post <- epd[epd$curve == "posterior", ]
  area <- sum(diff(post$value) * (head(post$density, -1) + tail(post$density, -1)) / 2)
  expect_equal(area, 1, tolerance = 0.05)
})

test_that("an informative prior is drawn as its truncated normal", {
  dens <- bayesbem:::prior_density(prior_normal(15, 0.2), c(10, 15, 20), lo = 5, hi = 25)
  u <- c(0.25, 0.5, 0.75)
  expected <- dnorm(u, 0.5, 0.2) / (pnorm(1, 0.5, 0.2) - pnorm(0, 0.5, 0.2)) / 20
  expect_equal(dens, expected)
})

test_that("plot_posteriors_data() is the kernel density of the draws", {
  d <- plot_posteriors_data(seb_fit, n_grid = 64)
  draws <- as.vector(bayesbem:::parameter_draws(seb_fit)[, "fan_total_efficiency"])
  lo <- min(seb_sim$fan_total_efficiency)
  hi <- max(seb_sim$fan_total_efficiency)
  expected <- stats::density(draws, from = lo, to = hi, n = 64)$y
  post <- d[d$parameter == "fan_total_efficiency" & d$curve == "posterior", ]
  expect_equal(post$density, expected, tolerance = 1e-8)
})

# drawn from the shipped seb_fit, whose draws are the same on every machine
test_that("plot_posteriors() draws the paper's Fig 5", {
  skip_if_not_installed("vdiffr")
  p <- plot_posteriors(seb_fit)
  expect_s3_class(p, "ggplot")
  vdiffr::expect_doppelganger("posteriors", p)
})
