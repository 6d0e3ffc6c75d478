test_that("outputs in long tables become one data set each, standardised on their own", {
  withr::local_seed(31)
  tables <- random_outputs_data()
  d <- koh_data(tables$field, tables$sim)
  expect_s3_class(d, "bayesbem_outputs")
  expect_named(d$outputs, c("elec", "gas"))
  for (k in c("elec", "gas")) {
    one <- d$outputs[[k]]
    eta <- tables$sim$eta[tables$sim$output == k]
    expect_equal(one$scaling$y_center, mean(eta))
    expect_equal(one$scaling$y_scale, stats::sd(eta))
    expect_equal(one$y * one$scaling$y_scale + one$scaling$y_center,
                 tables$field$y[tables$field$output == k])
    expect_false(is.null(one$grid))
  }
  # gas has one field row fewer (a missing month) and the same runs
  expect_equal(c(d$outputs$elec$n, d$outputs$gas$n), c(7L, 6L))
  expect_identical(unname(d$outputs$gas$grid$design), unname(d$outputs$elec$grid$design))
  expect_identical(d$outputs$gas$scaling$t_min, d$outputs$elec$scaling$t_min)
  expect_identical(d$names$t, c("k1", "k2", "k3"))
})

test_that("the outputs share one scale per parameter", {
  expect_equal(bayesbem:::shared_scales(list(c(a = "identity", b = "log", c = "identity"),
                                             c(a = "reciprocal", b = "identity", c = "identity"))),
               c(a = "reciprocal", b = "log", c = "identity"))
})

test_that("mismatched outputs and runs are classed errors that name them", {
  withr::local_seed(32)
  withr::local_options(cli.num_colors = 1)
  tables <- random_outputs_data()
  no_gas_runs <- tables$sim[tables$sim$output != "gas", ]
  expect_error(koh_data(tables$field, no_gas_runs), class = "bayesbem_error_outputs")
  expect_snapshot(koh_data(tables$field, no_gas_runs), error = TRUE)
  typo <- tables$field
  typo$output[typo$output == "gas"] <- "Gas"
  expect_snapshot(koh_data(typo, tables$sim), error = TRUE)
  other_runs <- tables$sim
  gas <- other_runs$output == "gas"
  other_runs$k1[gas] <- other_runs$k1[gas] + 0.01
  expect_snapshot(koh_data(tables$field, other_runs), error = TRUE)
  # an error in one output's data names the output
  bad <- tables$field
  bad$y[bad$output == "gas"][2] <- NA
  err <- expect_error(koh_data(bad, tables$sim), class = "bayesbem_error_missing")
  expect_match(conditionMessage(err), "gas", fixed = TRUE)
  expect_snapshot(koh_data(tables$field, tables$sim, output = "meter"), error = TRUE)
  numeric_output <- tables$field
  numeric_output$output <- as.integer(factor(numeric_output$output))
  expect_snapshot(koh_data(numeric_output, tables$sim), error = TRUE)
})
