test_that("a table study calibrates the first k ranked parameters", {
  skip_on_cran()
  ranking <- c("equipment_power_density", "infiltration_per_exterior_area",
               "fan_total_efficiency")
  study <- suppressWarnings(
    study_parameters(seb_field, seb_sim, ranking = ranking, k = c(1, 3), chains = 2,
                     iter = 600, cores = 2, seed = test_seed(4), refresh = 0),
    classes = "bayesbem_warning_convergence")
  expect_s3_class(study, "bayesbem_parameter_study")
  expect_named(study$fits, c("k = 1", "k = 3"))
  expect_equal(study$fits[["k = 1"]]$data$names$t, ranking[1])
  expect_equal(study$fits[["k = 3"]]$data$names$t, ranking)
  post <- study$posteriors
  expect_equal(post$k, c("k = 1", rep("k = 3", 3)))
  expect_true(all(post$scaled >= 0 & post$scaled <= 1))
  expect_equal(unique(study$metrics$set), "training")
  d <- plot_parameter_study_data(study)
  expect_equal(levels(d$k), c("1", "3"))
  expect_equal(levels(d$parameter), ranking)
  expect_s3_class(plot(study), "ggplot")
  expect_output(print(study), "top k = 1 and 3")
})

test_that("a simulator study designs and runs each k, others at initial values", {
  skip_on_cran()
  sim <- bem_simulator(shipped_epw(2013))
  field <- simulate_field(sim, list(equipment_power_density = 15), noise_sd = 10,
                          seed = 1)[c("y", "temp", "rh", "solar")]
  # two internal gains: the data fix their sum, not each one
  ranking <- c("equipment_power_density", "lighting_power_density")
  study <- suppressWarnings(
    study_parameters(field, sim, ranking = ranking, k = 1:2, n_runs = 10, chains = 2,
                     iter = 400, cores = 2, seed = test_seed(2), refresh = 0,
                     newdata = field[1:3, ], obs = field$y[1:3]),
    classes = "bayesbem_warning_convergence")
  runs <- study$fits[["k = 1"]]$data$sim
  expect_equal(names(runs), c("eta", "temp", "rh", "solar", "equipment_power_density"))
  expect_equal(nrow(runs), 10 * 12)
  expect_equal(study$fits[["k = 2"]]$data$names$t, ranking)
  # the runs hold lighting at its initial value when it is not calibrated
  p <- stats::setNames(as.list(sim$parameters$initial), sim$parameters$parameter)
  p$equipment_power_density <- runs$equipment_power_density[1]
  expect_equal(runs$eta[1:12], sim$fun(p, sim$x))
  expect_equal(study$metrics$set, rep(c("training", "held-out"), 2))
  # over-parameterisation (the paper's Fig 4): with both gains free the
  # equipment power density is far less certain
  epd <- study$posteriors[study$posteriors$parameter == ranking[1], ]
  expect_gt(epd$sd[2], 2 * epd$sd[1])
})

test_that("a Morris screening gives the ranking", {
  m <- structure(data.frame(parameter = c("b", "a"), mu_star = c(2, 1), mu = 0, sigma = 0,
                            rank = c(1, 2)), class = c("bayesbem_morris", "data.frame"))
  expect_equal(bayesbem:::study_ranking(m, c("a", "b"), 1:2), c("b", "a"))
})

test_that("bad rankings and k get classed errors", {
  expect_snapshot(study_parameters(seb_field, seb_sim, ranking = c("fan_total_efficiency", "wall")),
                  error = TRUE)
  expect_snapshot(study_parameters(seb_field, seb_sim, k = 2:4), error = TRUE)
  expect_error(study_parameters(seb_field, seb_sim, k = 0), class = "bayesbem_error_argument")
  expect_error(study_parameters(seb_field, seb_sim, ranking = 1:3),
               class = "bayesbem_error_argument")
  expect_error(study_parameters(seb_field, seb_sim, k = 1:3, newdata = seb_field[-2],
                                obs = seb_field$y),
               class = "bayesbem_error_columns")
  expect_error(study_parameters(seb_field, seb_sim, k = 1:3, newdata = seb_field),
               class = "bayesbem_error_argument")
  expect_error(plot_parameter_study(seb_fit), class = "bayesbem_error_argument")
})
