test_that("koh_data() scales as the method says", {
  d <- koh_data(seb_field, seb_sim)
  expect_s3_class(d, "bayesbem_data")
  expect_equal(c(d$n, d$m, d$p, d$q), c(12, 120, 3, 3))
  expect_equal(d$scaling$y_center, mean(seb_sim$eta))
  expect_equal(d$scaling$y_scale, sd(seb_sim$eta))
  expect_equal(mean(d$eta), 0)
  expect_equal(sd(d$eta), 1)
  # x over field and simulation rows together, t over the design
  all_x <- rbind(d$xf, d$xc)
  expect_equal(unname(apply(all_x, 2, range)), matrix(c(0, 1), 2, 3))
  expect_equal(unname(apply(d$tc, 2, range)), matrix(c(0, 1), 2, 3))
  expect_equal(d$scaling$t_min[["equipment_power_density"]], min(seb_sim$equipment_power_density))
})

test_that("scaling round-trips", {
  d <- koh_data(seb_field, seb_sim)
  s <- d$scaling
  expect_equal(bayesbem:::unscale_y(d$y, s), seb_field$y, tolerance = 1e-12)
  expect_equal(bayesbem:::unscale_y(d$eta, s), seb_sim$eta, tolerance = 1e-12)
  expect_equal(unname(bayesbem:::unscale_x(d$xf, s)), unname(as.matrix(seb_field[2:4])),
               tolerance = 1e-12)
  expect_equal(unname(bayesbem:::unscale_t(d$tc, s)), unname(as.matrix(seb_sim[5:7])),
               tolerance = 1e-12)
})

test_that("columns can be given by name, in any order", {
  by_pos <- koh_data(seb_field, seb_sim)
  shuffled <- seb_sim[c(7, 2, 1, 5, 4, 3, 6)]
  by_name <- koh_data(seb_field[c(3, 1, 4, 2)], shuffled, y = "y", eta = "eta",
                      x = c("temp", "rh", "solar"),
                      t = c("fan_total_efficiency", "equipment_power_density",
                            "infiltration_per_exterior_area"))
  expect_equal(by_name$xc, by_pos$xc)
  expect_equal(by_name$tc, by_pos$tc)
  expect_equal(by_name$y, by_pos$y)
})

test_that("the paper's column layout works by position once the outputs are named", {
  field <- setNames(seb_field[1:4], c("yf", "xf1", "xf2", "xf3"))
  sim <- setNames(seb_sim, c("yc", "xc1", "xc2", "xc3", "tc1", "tc2", "tc3"))
  expect_error(koh_data(field, sim), class = "bayesbem_error_columns")
  d <- koh_data(field, sim, y = "yf", eta = "yc")
  expect_equal(d$names$t, c("tc1", "tc2", "tc3"))
  expect_equal(d$xc, koh_data(seb_field, seb_sim)$xc, ignore_attr = TRUE)
})

test_that("the outputs are found by name, never by position", {
  withr::local_options(cli.num_colors = 1)
  # a bill column last: not temperature taken for the output
  kwh <- data.frame(seb_field[c("temp", "rh", "solar")], kwh = seb_field$y)
  expect_snapshot(koh_data(kwh, seb_sim), error = TRUE)
  expect_equal(koh_data(kwh, seb_sim, y = "kwh")$names$y, "kwh")
  # the runs' output may carry the field output's name
  runs <- seb_sim[c(2:7, 1)]
  names(runs)[7] <- "kwh"
  d <- koh_data(kwh, runs, y = "kwh")
  expect_equal(d$names$eta, "kwh")
  expect_equal(d$eta, koh_data(seb_field, seb_sim)$eta)
  expect_snapshot(koh_data(seb_field, setNames(seb_sim, c("out", names(seb_sim)[-1]))),
                  error = TRUE)
})

test_that("bad input gets classed errors that say what to fix", {
  withr::local_options(cli.num_colors = 1)
  bad_na <- seb_field
  bad_na$rh[c(2, 5)] <- NA
  expect_error(koh_data(bad_na, seb_sim), class = "bayesbem_error_missing")
  expect_snapshot(koh_data(bad_na, seb_sim), error = TRUE)

  bad_chr <- seb_sim
  bad_chr$fan_total_efficiency <- as.character(bad_chr$fan_total_efficiency)
  expect_error(koh_data(seb_field, bad_chr), class = "bayesbem_error_non_numeric")
  expect_snapshot(koh_data(seb_field, bad_chr), error = TRUE)

  expect_error(koh_data(seb_field, seb_sim[1:4]), class = "bayesbem_error_columns")
  expect_snapshot(koh_data(seb_field, seb_sim[1:4]), error = TRUE)
  expect_snapshot(koh_data(seb_field, seb_sim, x = c("temp", "wind")), error = TRUE)

  flat_x <- seb_field
  flat_x$rh <- 50
  flat_sim <- seb_sim
  flat_sim$rh <- 50
  expect_error(koh_data(flat_x, flat_sim), class = "bayesbem_error_constant")
  flat_t <- seb_sim
  flat_t$equipment_power_density <- 10
  expect_snapshot(koh_data(seb_field, flat_t), error = TRUE)

  # runs that never respond: the field's level is out of reach, not a column to drop
  flat_eta <- seb_sim
  flat_eta$eta <- 0
  expect_error(koh_data(seb_field, flat_eta), class = "bayesbem_error_prior_misses")
  expect_snapshot(koh_data(seb_field, flat_eta), error = TRUE)
  both_flat <- seb_field
  both_flat$y <- 0
  expect_error(koh_data(both_flat, flat_eta), class = "bayesbem_error_constant")

  expect_error(koh_data(seb_field[1, ], seb_sim), class = "bayesbem_error_too_few_rows")
  expect_snapshot(koh_data(seb_field[1, ], seb_sim), error = TRUE)
  expect_error(koh_data(seb_field, seb_sim[1:4, ]), class = "bayesbem_error_too_few_rows")
  expect_snapshot(koh_data(seb_field, seb_sim[1:4, ]), error = TRUE)

  expect_snapshot(koh_data(list(1, 2), seb_sim), error = TRUE)

  repeated <- seb_sim[c(1:120, 5, 17), ]
  expect_error(koh_data(seb_field, repeated), class = "bayesbem_error_duplicated")
  expect_snapshot(koh_data(seb_field, repeated), error = TRUE)
})

test_that("inputs are matched by name: a column in one table only is an error", {
  withr::local_options(cli.num_colors = 1)
  # seb_sim has solar, the field table does not: solar is no parameter
  field <- seb_field[c("y", "temp", "rh")]
  expect_error(koh_data(field, seb_sim), class = "bayesbem_error_columns")
  expect_snapshot(koh_data(field, seb_sim), error = TRUE)
  # naming x and t says what is what
  d <- koh_data(field, seb_sim, x = c("temp", "rh"), t = "equipment_power_density")
  expect_equal(d$names$t, "equipment_power_density")
  # a field input the simulation table lacks
  wind <- cbind(seb_field, wind = 1:12)
  expect_error(koh_data(wind, seb_sim), class = "bayesbem_error_columns")
  expect_snapshot(koh_data(wind, seb_sim), error = TRUE)
  # inputs in another order are matched by name, not position
  shuffled <- seb_sim[c("eta", "solar", "temp", "rh", "fan_total_efficiency",
                        "equipment_power_density", "infiltration_per_exterior_area")]
  expect_equal(koh_data(seb_field, shuffled)$xc, koh_data(seb_field, seb_sim)$xc)
})

test_that("a date column dates the rows and is not an input", {
  withr::local_options(cli.num_colors = 1)
  d <- koh_data(seb_field, seb_sim)
  expect_equal(d$names$period, "month")
  expect_equal(d$names$x, c("temp", "rh", "solar"))
  expect_equal(bayesbem:::period_labels(d)[c(1, 12)], c("Jan 2013", "Dec 2013"))
  expect_output(print(d), "rows dated by month: Jan 2013 to Dec 2013")
  daily <- seb_field
  daily$month <- as.Date("2013-03-05") + 0:11
  expect_equal(bayesbem:::period_labels(koh_data(daily, seb_sim))[1], "2013-03-05")
  expect_null(koh_data(seb_field[1:4], seb_sim)$names$period)
  expect_equal(bayesbem:::period_labels(koh_data(seb_field[1:4], seb_sim))[1:2], c("1", "2"))
  two <- cbind(seb_field, read = seb_field$month + 27)
  expect_snapshot(koh_data(two, seb_sim), error = TRUE)
  chosen <- koh_data(two, seb_sim, x = c("temp", "rh", "solar"), period = "read")
  expect_equal(bayesbem:::period_labels(chosen)[1], "2013-01-28")
  expect_snapshot(koh_data(seb_field, seb_sim, period = "temp"), error = TRUE)
})

test_that("an input column that is all NA is called missing", {
  withr::local_options(cli.num_colors = 1)
  expect_snapshot(predict(seb_fit, data.frame(temp = NA, rh = 40, solar = 200)), error = TRUE)
})

test_that("outputs in other units are an error that names both sizes", {
  withr::local_options(cli.num_colors = 1)
  joules <- transform(seb_sim, eta = eta * 3.6e6)
  expect_snapshot(koh_data(seb_field, joules), error = TRUE)
  expect_error(koh_data(seb_field, transform(seb_sim, eta = eta * 11)),
               class = "bayesbem_error_units")
  # within an order of magnitude is the calibration's business
  expect_no_error(koh_data(seb_field, transform(seb_sim, eta = eta * 3)))
})

test_that("field rows of other periods than the runs' are named as such", {
  withr::local_options(cli.num_colors = 1)
  epw <- shipped_epw(2013)
  pars <- bem_parameters()
  pars <- pars[pars$parameter %in% c("equipment_power_density", "infiltration_per_exterior_area"), ]
  monthly_runs <- simulate_design(bem_simulator(epw), design_lhs(pars, 6, seed = 1))
  weekly <- simulate_field(bem_simulator(epw_weather(epw, by = "week")),
                           list(equipment_power_density = 15), noise_sd = 5, seed = 2)
  expect_snapshot(koh_data(weekly, monthly_runs), error = TRUE)
  # the same periods in other units stay a units error
  expect_error(koh_data(seb_field, transform(seb_sim, eta = eta * 11)),
               class = "bayesbem_error_units")
})

test_that("estimated readings are left out with a message", {
  field <- seb_field
  field$estimated <- seq_len(12) %in% c(3, 7)
  expect_message(d <- koh_data(field, seb_sim), "rows 3 and 7", class = "bayesbem_message_estimated")
  expect_equal(d$n, 10)
  expect_equal(d$field$y, seb_field$y[-c(3, 7)])
  expect_false("estimated" %in% d$names$x)
  field$estimated <- FALSE
  expect_no_message(koh_data(field, seb_sim), class = "bayesbem_message_estimated")
  field$estimated <- "no"
  expect_error(koh_data(field, seb_sim), class = "bayesbem_error_columns")
  field$estimated <- c(NA, rep(FALSE, 11))
  expect_error(koh_data(field, seb_sim), class = "bayesbem_error_columns")
})
