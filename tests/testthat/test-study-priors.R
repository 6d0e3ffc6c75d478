# Prior means at the simulator's initial values, infiltration at the top of
# the shipped design's range (its initial value, 0.001524, lies above it)
seb_mu <- c(fan_total_efficiency = 0.5, equipment_power_density = 21.9,
            infiltration_per_exterior_area = 0.00135)
seb_held_out <- c(3, 7, 11)

prior_study <- local({
  study <- NULL
  function() {
    if (is.null(study)) {
      study <<- suppressWarnings(
        study_priors(seb_field[-seb_held_out, ], seb_sim, mu = seb_mu,
                     newdata = seb_field[seb_held_out, ],
                     obs = seb_field$y[seb_held_out], chains = 2, iter = 600, cores = 2,
                     seed = test_seed(3), refresh = 0),
        classes = "bayesbem_warning_convergence")
    }
    study
  }
})

test_that("a specific prior pulls the posterior to its mean and narrows it", {
  skip_on_cran()
  study <- prior_study()
  expect_s3_class(study, "bayesbem_prior_study")
  expect_named(study$fits, c("flat", "weak", "specific"))
  post <- study$posteriors
  for (name in names(seb_mu)) {
    p <- post[post$parameter == name, ]
    expect_lt(p$sd[p$strength == "specific"], p$sd[p$strength == "flat"], label = name)
    expect_lt(abs(p$mean[p$strength == "specific"] - seb_mu[[name]]),
              abs(p$mean[p$strength == "flat"] - seb_mu[[name]]), label = name)
  }
  # each fit got its strength's priors
  expect_equal(study$fits$specific$priors$tf$equipment_power_density$sd, 0.05)
  expect_equal(study$fits$weak$priors$tf$fan_total_efficiency$sd, 0.2)
  expect_equal(study$fits$flat$priors$tf$fan_total_efficiency$family, "uniform")
})

test_that("the metrics table has training and held-out rows per strength (Table 3)", {
  skip_on_cran()
  m <- prior_study()$metrics
  expect_equal(m$strength, rep(c("flat", "weak", "specific"), each = 2))
  expect_equal(m$set, rep(c("training", "held-out"), 3))
  expect_equal(m$n, rep(c(9, 3), 3))
  # the discrepancy absorbs what the priors cost: every strength fits the training data
  expect_true(all(m$cvrmse[m$set == "training"] < 5))
  expect_output(print(prior_study()), "CVRMSE and NMBE")
})

test_that("the prior study plot shows each strength's posterior", {
  skip_on_cran()
  d <- plot_prior_study_data(prior_study())
  expect_named(d, c("strength", "parameter", "value", "density"))
  expect_equal(levels(d$strength), c("flat", "weak", "specific"))
  expect_equal(nrow(d), 3 * 3 * 200)
  expect_s3_class(plot(prior_study()), "ggplot")
  # a study stored without its fits still prints and plots
  small <- prior_study()
  small$fits <- NULL
  expect_identical(plot_prior_study_data(small), d)
  expect_output(print(small), "3 prior strengths")
})

test_that("fits run through future and report progress", {
  skip_on_cran()
  skip_if_not_installed("future")
  one <- function() {
    study_priors(seb_field, seb_sim, strengths = "flat", chains = 1, iter = 200, seed = test_seed(5),
                 refresh = 0)
  }
  withr::local_options(progressr.enable = TRUE)
  steps <- 0
  sequential <- suppressWarnings(withCallingHandlers(
    one(), progression = function(c) steps <<- steps + 1
  ))
  expect_gte(steps, 2)
  oplan <- future::plan(future::multisession, workers = 2)
  on.exit(future::plan(oplan), add = TRUE)
  parallel <- suppressWarnings(one())
  expect_equal(parallel$posteriors, sequential$posteriors)
})

test_that("bad study arguments get classed errors", {
  expect_snapshot(study_priors(seb_field, seb_sim, strengths = "vague"), error = TRUE)
  expect_error(study_priors(seb_field, seb_sim, strengths = c("flat", "flat")),
               class = "bayesbem_error_argument")
  expect_snapshot(study_priors(seb_field, seb_sim, strengths = "weak"), error = TRUE)
  expect_snapshot(study_priors(seb_field, seb_sim, strengths = "specific",
                               mu = c(seb_mu[1:2], infiltration_per_exterior_area = 0.002)),
                  error = TRUE)
  expect_error(study_priors(seb_field, seb_sim, newdata = seb_field[, 1:2], obs = seb_field$y,
                            strengths = "flat"),
               class = "bayesbem_error_columns")
  expect_error(study_priors(seb_field, seb_sim, newdata = seb_field, obs = seb_field$y[-1],
                            strengths = "flat"),
               class = "bayesbem_error_argument")
  expect_error(plot_prior_study(seb_fit), class = "bayesbem_error_argument")
})
