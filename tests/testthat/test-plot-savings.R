test_that("plot_savings_data() summarises the paired draws per period and in total", {
  sim <- linear_seb_simulator()
  s <- savings(seb_fit, sim, scenario(sim, scale = c(equipment_power_density = 0.7)),
               ndraws = 20)
  d <- plot_savings_data(s)
  expect_equal(nrow(d), ncol(s$savings))
  expect_equal(d$q50, unname(apply(s$savings, 2, stats::median)))
  expect_equal(d$mean, unname(colMeans(s$savings)))
  expect_true(all(d$q5 <= d$q25 & d$q25 <= d$q50 & d$q50 <= d$q75 & d$q75 <= d$q95))
  expect_equal(attr(d, "total")$mean, mean(rowSums(s$savings)))
  # the total's interval is the summary's
  total <- summary(s)[ncol(s$savings) + 1L, ]
  expect_equal(unlist(attr(d, "total")[c("q5", "q95")]), c(q5 = total$lower, q95 = total$upper))
  p <- plot_savings(s)
  expect_s3_class(p, "ggplot")
  expect_identical(plot(s)$data, p$data)
  expect_error(plot_savings_data(seb_fit), class = "bayesbem_error_argument")
  expect_error(plot(s, bins = 3), class = "rlib_error_dots_nonempty")
})

# drawn from the shipped seb_fit with a fixed seed: the same on every machine
test_that("plot_savings() draws", {
  skip_if_not_installed("vdiffr")
  withr::local_seed(5)
  sim <- linear_seb_simulator()
  s <- savings(seb_fit, sim, scenario(sim, scale = c(equipment_power_density = 0.7)),
               ndraws = 20)
  vdiffr::expect_doppelganger("savings", plot_savings(s))
})
