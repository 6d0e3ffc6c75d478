test_that("the Stan log density equals the method's, computed independently in R", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim)
  withr::local_seed(42)
  # each emulator mean: the linear default, and the paper's zero mean
  for (emulator_mean in c("linear", "zero")) {
    priors <- koh_priors(tf = prior_strength("weak", c(equipment_power_density = 20,
                                                       infiltration_per_exterior_area = 0.0008)),
                         emulator_mean = emulator_mean)
    sd <- bayesbem:::koh_stan_data(d, priors)
    expect_equal(sd$n_b, if (emulator_mean == "zero") 0 else 7)
    expect_log_density_matches(sd, 4)
  }
})

test_that("on log and reciprocal scales the priors stay in physical units", {
  skip_on_cran()
  d <- koh_data(seb_field, seb_sim, scales = c(fan_total_efficiency = "reciprocal",
                                               infiltration_per_exterior_area = "log"))
  withr::local_seed(43)
  # a flat prior on the reciprocal scale, normal priors on each scale
  for (fan in list(NULL, prior_normal(0.5, 0.3))) {
    priors <- koh_priors(tf = c(if (!is.null(fan)) list(fan_total_efficiency = fan),
                                prior_strength("weak", c(equipment_power_density = 20,
                                                         infiltration_per_exterior_area = 0.0008))))
    sd <- bayesbem:::koh_stan_data(d, priors)
    expect_equal(as.vector(sd$tf_scale), c(2, 0, 1))
    expect_log_density_matches(sd, 2)
  }
})

test_that("the Stan log density matches on other sizes, with outputs sampled in Stan", {
  skip_on_cran()
  withr::local_seed(7)
  n <- 5
  runs <- 6
  x <- matrix(runif(n * 2), n, 2, dimnames = list(NULL, c("a", "b")))
  design <- cbind(k1 = runif(runs, 0, 3), k2 = runif(runs, 10, 20), k3 = runif(runs))
  sim <- do.call(rbind, lapply(seq_len(runs), function(r) {
    data.frame(eta = rnorm(n, 5), x, t(design[r, ]))
  }))
  field <- data.frame(y = rnorm(n, 5), x)
  d <- koh_data(field, sim)
  sd <- bayesbem:::koh_stan_data(d, koh_priors(tf = list(k2 = prior_normal(12, 0.05)),
                                               nugget = 1e-4),
                                 x_pred = matrix(runif(4), 2, 2))
  expect_log_density_matches(sd, 3)
})

test_that("the grid program's log density equals the dense program's", {
  skip_on_cran()
  withr::local_seed(11)
  # with two parametric discrepancy terms (extend())
  random <- bayesbem:::add_discrepancy_terms(random_grid_data(extra = 2),
                                             data.frame(w1 = rnorm(7), w2 = rep(0:1, c(3, 4))))
  bounds <- bayesbem:::t_bounds(random$scaling)
  k2_mid <- (bounds$lower[["k2"]] + bounds$upper[["k2"]]) / 2
  problems <- list(
    shipped = list(d = koh_data(seb_field, seb_sim),
                   priors = koh_priors(tf = prior_strength("weak", c(equipment_power_density = 20)),
                                       emulator_mean = "zero")),
    random = list(d = random, priors = koh_priors(tf = list(k2 = prior_normal(k2_mid, 0.05)),
                                                  nugget = 1e-4)),
    periods = list(d = random_grid_data(extra = 1, days = TRUE),
                   priors = koh_priors(nugget = 1e-4)),
    constant = list(d = random_grid_data(extra = 0),
                    priors = koh_priors(emulator_mean = "constant", mean_sd = 0.5,
                                        rho_eta = c(2, 0.3), rho_delta = c(1.5, 0.5)))
  )
  expect_equal(random$grid$n_x, 9)
  for (pr in problems) {
    dense <- bayesbem:::koh_stan_data(pr$d, pr$priors, structure = "dense")
    grid <- bayesbem:::koh_stan_data(pr$d, pr$priors, structure = "grid")
    model_dense <- koh_model_for(dense)
    model_grid <- koh_model_for(grid)
    for (i in 1:4) {
      pars <- random_koh_pars(dense)
      lp_grid <- stan_log_density(model_grid, pars[names(pars) != "y_pred"])
      expect_equal(lp_grid, stan_log_density(model_dense, pars), tolerance = 1e-8)
      expect_equal(lp_grid, reference_log_density(dense, pars), tolerance = 1e-8)
    }
  }
})

# The grid and modular likelihoods' data and random parameters for the data d.
field_density_models <- function(d) {
  priors <- koh_priors(tf = list(k1 = prior_normal(1.5, 0.2)), nugget = 1e-4)
  grid <- bayesbem:::koh_stan_data(d, priors, structure = "grid")
  pars <- random_koh_pars(bayesbem:::koh_stan_data(d, priors, structure = "dense"))
  emulator <- list(beta_eta = -4 * log(pars$rho_eta), lambda_eta = pars$lambda_eta, b = pars$b)
  list(
    grid = list(sd = grid, pars = pars[names(pars) != "y_pred"]),
    modular = list(sd = bayesbem:::modular_stan_data(d, priors, emulator),
                       pars = stage2_pars(pars))
  )
}

# Checks both likelihoods at random parameters of the data d (test below).
expect_gradient_matches <- function(d) {
  models <- field_density_models(d)
  for (likelihood in names(models)) {
    model <- koh_model_for(models[[likelihood]]$sd)
    upars <- unconstrain(model, models[[likelihood]]$pars)
    numeric_grad <- vapply(seq_along(upars), function(k) {
      h <- 1e-5 * replace(numeric(length(upars)), k, 1)
      (rstan::log_prob(model, upars + h) - rstan::log_prob(model, upars - h)) / 2e-5
    }, numeric(1))
    grad <- rstan::grad_log_prob(model, upars)
    expect_equal(as.vector(grad), numeric_grad, tolerance = 1e-6)
  }
}

# The field density of the grid and modular likelihoods has a hand-written
# gradient (inst/include/normal_two_kernels.hpp); Stan's gradient must equal
# central finite differences of Stan's own log density. At n = 70 the inverse
# of Sigma recurses three times, into unequal halves (invert_lower(), halves
# down to 16 rows).
test_that("the grid and modular gradients equal finite differences", {
  skip_on_cran()
  withr::local_seed(12)
  for (n in c(7, 70)) expect_gradient_matches(random_grid_data(n = n, extra = 2))
  # each row's noise variance its own (periods of different lengths)
  expect_gradient_matches(random_grid_data(n = 9, extra = 2, days = TRUE))
})

# normal_two_kernels_lpdf() factors Sigma by Eigen or by R's LAPACK, as
# use_lapack() chooses: both must give the same log density and gradient.
test_that("R's LAPACK and Eigen give the same field density and gradient", {
  skip_on_cran()
  withr::local_seed(13)
  models <- field_density_models(random_grid_data(n = 70, extra = 2))
  for (likelihood in names(models)) {
    at <- lapply(0:1, function(lapack) {
      model <- koh_model_for(utils::modifyList(models[[likelihood]]$sd, list(lapack = lapack)))
      u <- unconstrain(model, models[[likelihood]]$pars)
      list(lp = rstan::log_prob(model, u), grad = as.vector(rstan::grad_log_prob(model, u)))
    })
    expect_equal(at[[2]]$lp, at[[1]]$lp, tolerance = 1e-10)
    expect_equal(at[[2]]$grad, at[[1]]$grad, tolerance = 1e-8)
  }
})

test_that("a covariance that is not positive definite is an error on both paths", {
  skip_on_cran()
  withr::local_seed(13)
  m <- field_density_models(random_grid_data(n = 7, extra = 2))$modular
  m$sd$Kx_ff <- -1e12 * diag(nrow(m$sd$Kx_ff))
  for (lapack in 0:1) {
    model <- koh_model_for(utils::modifyList(m$sd, list(lapack = lapack)))
    u <- unconstrain(model, m$pars)
    expect_error(rstan::log_prob(model, u), "not positive definite")
  }
})

test_that("a failing Cholesky factor is named, with the fix", {
  skip_on_cran()
  # months 1 and 2 at inputs 1e-10 apart: K_x is singular without a nugget
  x <- c("temp", "rh", "solar")
  index <- koh_data(seb_field, seb_sim)$grid$index
  field <- seb_field
  field[x] <- seb_sim[index[, 1], x]
  field[2, x] <- field[1, x] + c(1e-10, 0, 0)
  sim <- seb_sim
  sim[index, x] <- field[row(index), x]
  d <- koh_data(field, sim, grid_tol = 0)
  expect_false(is.null(d$grid))
  expect_error(calibrate(d, priors = koh_priors(nugget = 0), chains = 1, iter = 20, seed = test_seed(1),
                         refresh = 0),
               class = "bayesbem_error_cholesky")
  expect_snapshot(
    calibrate(d, priors = koh_priors(nugget = 0), chains = 1, iter = 20, seed = 1, refresh = 0),
    error = TRUE
  )
})

test_that("a small fit of the case study finds the equipment power density", {
  skip_on_cran()
  fit <- shared_fit()
  expect_s3_class(fit, "bayesbem_fit")
  s <- summary(fit)
  epd <- s$parameters[s$parameters$variable == "equipment_power_density", ]
  expect_gt(epd$mean, 8)
  expect_lt(epd$mean, 17)
  expect_lt(epd$rhat, 1.05)
  # everything reported for tf is inside the design range, in physical units
  draws <- posterior::as_draws_df(fit)
  expect_true(all(draws$equipment_power_density >= min(seb_sim$equipment_power_density)))
  expect_true(all(draws$equipment_power_density <= max(seb_sim$equipment_power_density)))
})

test_that("calibrate() rejects bad arguments with classed errors", {
  expect_error(calibrate(seb_field, seb_sim, chains = 2.5), class = "bayesbem_error_argument")
  expect_snapshot(calibrate(seb_field, seb_sim, chains = 0), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, iter = "500"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, iter = 100, warmup = 100), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, priors = list()), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, control = 0.95), error = TRUE)
})

test_that("control entries replace the defaults one by one", {
  merge <- bayesbem:::merge_control
  basis <- list(adapt_delta = 0.95, metric = "dense_e")
  expect_equal(merge(NULL, basis), basis)
  expect_equal(merge(list(max_treedepth = 12), basis),
               list(adapt_delta = 0.95, metric = "dense_e", max_treedepth = 12))
  expect_equal(merge(list(adapt_delta = 0.8), basis), list(adapt_delta = 0.8, metric = "dense_e"))
  expect_error(merge(list(adapt_dleta = 0.9), basis), class = "bayesbem_error_argument")
  expect_error(merge(list(0.9), basis), class = "bayesbem_error_argument")
  # what the fit records is the merged list
  withr::local_options(bayesbem.progress = FALSE)
  fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 1, iter = 40, seed = test_seed(1),
                                    control = list(max_treedepth = 5), refresh = 0),
                          classes = "bayesbem_warning_convergence")
  expect_equal(fit$settings$control, list(adapt_delta = 0.99, max_treedepth = 5))
  expect_equal(bayesbem:::sampler_params(fit)[[1]][, "treedepth__"] <= 5,
               rep(TRUE, 20))
})

test_that("sampler control given as an argument points to `control`", {
  withr::local_options(cli.num_colors = 1)
  expect_snapshot(calibrate(seb_field, seb_sim, adapt_delta = 0.99), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, control = list(adapt_dleta = 0.9)), error = TRUE)
})

test_that("chains run on every core by default, two under R CMD check's limit", {
  withr::local_envvar(`_R_CHECK_LIMIT_CORES_` = "")
  expect_equal(bayesbem:::default_cores(), parallel::detectCores())
  withr::local_envvar(`_R_CHECK_LIMIT_CORES_` = "TRUE")
  expect_equal(bayesbem:::default_cores(), min(parallel::detectCores(), 2L))
})

test_that("wrong argument types say what they are", {
  withr::local_options(cli.num_colors = 1)
  expect_snapshot(calibrate(seb_field, seb_sim, iter = "500"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, chains = 0), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, seed = "x"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, structure = "grd"), error = TRUE)
  expect_snapshot(calibrate(seb_field, seb_sim, n_draws = 10), error = TRUE)
  expect_error(calibrate(seb_field, seb_sim, iter = 1.5), class = "bayesbem_error_argument")
})

# The defaults by size and emulator (bench/results/reliability.md)
test_that("default sampling depends on the kind of fit and the data size", {
  careful <- list(iter = 4000L, warmup = 2000L, control = list(adapt_delta = 0.99))
  expect_equal(bayesbem:::default_sampling(FALSE, 12), careful)
  expect_equal(bayesbem:::default_sampling(FALSE, 120), careful)
  expect_equal(bayesbem:::default_sampling(TRUE, 36), careful)
  expect_equal(bayesbem:::default_sampling(TRUE, 37),
               list(iter = 2000L, warmup = 1000L, control = list(adapt_delta = 0.9)))
  expect_equal(bayesbem:::default_sampling(TRUE, 37, "basis"),
               list(iter = 3000L, warmup = 1000L,
                    control = list(adapt_delta = 0.95, metric = "dense_e")))
  expect_equal(bayesbem:::default_sampling(TRUE, 36, "basis"), careful)
  expect_equal(bayesbem:::default_sampling(TRUE, 8760, "basis", "additive"),
               list(iter = 2000L, warmup = 500L,
                    control = list(adapt_delta = 0.95, metric = "dense_e", max_treedepth = 8L,
                                   adapt_init_buffer = 25L)))
})

test_that("a caller's iter has half of it as warm-up, the defaults their own", {
  lengths <- bayesbem:::sampling_lengths
  basis <- bayesbem:::default_sampling(TRUE, 37, "basis")
  expect_equal(lengths(NULL, NULL, basis), list(iter = 3000L, warmup = 1000L))
  expect_equal(lengths(500, NULL, basis), list(iter = 500, warmup = 250))
  expect_equal(lengths(NULL, 200, basis), list(iter = 3000L, warmup = 200))
  expect_equal(lengths(1001, NULL, basis), list(iter = 1001, warmup = 500))
  expect_error(lengths(NULL, 3000, basis), class = "bayesbem_error_argument")
})

test_that("three years of bills with 30 runs converge with the defaults (a seeded problem)", {
  skip_on_cran()
  # problem 3 of bench/bench-reliability.R at n = 36, mt = 30 with its seed:
  # with the defaults (modular, 4000 iterations at adapt_delta 0.99) max
  # R-hat 1.003 and 2083 effective draws, under 2 minutes on 2 cores
  # (bench/results/)
  problem <- bayesbem:::synthetic_problem(36, 30, 3)
  expect_equal(nrow(problem$field), 36)
  fit <- calibrate(problem$field, problem$runs, seed = test_seed(4003), cores = 2)
  expect_true(fit$settings$modular)
  conv <- check_convergence(fit, warn = FALSE)
  expect_lt(max(conv$rhat), 1.01)
  expect_gte(min(conv$ess_bulk, conv$ess_tail), 400)
  expect_equal(attr(conv, "sampler")$divergent, 0)
  # the truth lies in the posterior's bulk: inside its central 98 % (the
  # 90 % interval's edge can pass the truth by Monte Carlo error alone)
  draws <- bayesbem:::parameter_draws(fit)
  for (p in names(problem$truth)) {
    q <- stats::quantile(draws[, p], c(0.01, 0.99))
    expect_true(problem$truth[[p]] >= q[[1]] && problem$truth[[p]] <= q[[2]], label = p)
  }
})

test_that("a fit too large for the machine's memory or time is refused before it runs", {
  small <- bayesbem:::fit_size(koh_data(seb_field, seb_sim), "grid", TRUE, 2000)
  expect_lt(small$hours, 0.01)
  expect_null(bayesbem:::check_fit_size(small, 4, available = 2^30))
  # memory: 4 chains of 1 GB against 3 GB available
  big <- list(bytes = 2^30, hours = 1, rows = 4000)
  expect_error(bayesbem:::check_fit_size(big, 4, available = 3 * 2^30),
               class = "bayesbem_error_too_large")
  expect_null(bayesbem:::check_fit_size(big, 2, available = 3 * 2^30))
  # time: over bayesbem.max_hours
  slow <- list(bytes = 2^31, hours = 30, rows = 1095)
  expect_snapshot(bayesbem:::check_fit_size(slow, 2, available = NA), error = TRUE)
  withr::local_options(bayesbem.max_hours = 48)
  expect_null(bayesbem:::check_fit_size(slow, 2, available = NA))
})

# A year of hourly inputs, temperatures to 0.1 C, and 30 runs of one parameter.
hourly_year <- function() {
  hours <- 8760
  list(x = data.frame(temp = round(stats::rnorm(hours, 10, 8), 1), hour = rep(0:23, 365),
                      day = rep(seq_len(365), each = 24)),
       design = data.frame(k = stats::runif(30, 1, 2)), hours = hours)
}

test_that("a year of hourly rows is prepared in bounded memory and refused up front", {
  skip_on_cran()
  withr::local_seed(9)
  year <- hourly_year()
  x <- year$x
  design <- year$design
  hours <- year$hours
  sim <- do.call(rbind, lapply(design$k, function(k) data.frame(eta = k * x$temp + x$hour, x, k = k)))
  field <- data.frame(y = 1.5 * x$temp + x$hour + stats::rnorm(hours), x)
  d <- koh_data(field, sim)
  expect_equal(c(d$grid$n, d$grid$mt), c(hours, 30))
  size <- bayesbem:::fit_size(d, "grid", TRUE, 2000)
  expect_gt(size$hours, 500)
  # the hours follow the iterations asked for
  expect_equal(bayesbem:::fit_size(d, "grid", TRUE, 500)$hours, size$hours / 4)
  # the product kernel is refused; "auto" takes the additive one at this size
  expect_error(calibrate(d, chains = 2, seed = 1, discrepancy_kernel = "product"),
               class = "bayesbem_error_too_large")
  # the additive discrepancy's factor has its basis functions' columns, not the rows
  additive <- bayesbem:::fit_size(d, "grid", TRUE, 3000, "additive")
  expect_equal(additive$rows, 40 * 3 + 10)
  expect_lt(additive$hours, 0.5)
})

test_that("the size check of a year of hours of two outputs says a number, and refuses only by it", {
  skip_on_cran()
  withr::local_seed(10)
  year <- hourly_year()
  x <- year$x
  design <- year$design
  hours <- year$hours
  meter <- function(output, a, b) {
    sim <- do.call(rbind, lapply(design$k, function(k) {
      data.frame(output = output, eta = a * k * x$temp + b * x$hour, x, k = k)
    }))
    field <- data.frame(output = output, y = a * 1.5 * x$temp + b * x$hour + stats::rnorm(hours), x)
    list(sim = sim, field = field)
  }
  elec <- meter("electricity", 1, 1)
  gas <- meter("gas", -2, 0.1)
  d <- koh_data(rbind(elec$field, gas$field), rbind(elec$sim, gas$sim))
  expect_s3_class(d, "bayesbem_outputs")
  size <- bayesbem:::fit_size(d, "grid", TRUE, 1000, "additive")
  # one factor of 40 basis functions per input and 10 components, per output
  expect_equal(size$rows, 40 * 3 + 10)
  single <- bayesbem:::fit_size(d$outputs$gas, "grid", TRUE, 1000, "additive")
  expect_equal(size$hours, 2 * single$hours)
  expect_equal(size$bytes, 2 * single$bytes)
  expect_null(bayesbem:::check_fit_size(size, 2, available = NA))
  # calibrate() reaches the check with a number: refused only when the limit is below it
  withr::local_options(bayesbem.max_hours = size$hours / 2)
  expect_error(calibrate(d, chains = 2, seed = 1, progress = FALSE),
               class = "bayesbem_error_too_large")
})

test_that("a meter no run reaches is reported before anything is fitted", {
  totals <- bayesbem:::prior_totals(koh_data(seb_field, seb_sim))
  expect_equal(totals$measured, sum(seb_field$y))
  runs <- split(seb_sim$eta, interaction(seb_sim[c("fan_total_efficiency", "equipment_power_density",
                                                    "infiltration_per_exterior_area")], drop = TRUE))
  expect_equal(sort(unname(totals$runs)), sort(unname(vapply(runs, sum, numeric(1)))))
  expect_null(bayesbem:::check_prior_covers(koh_data(seb_field, seb_sim)))
  # a building ten times the case study's: the bills ten times any run's
  big <- seb_field
  big$y <- 10 * big$y
  expect_snapshot(calibrate(big, seb_sim, chains = 1, seed = 1), error = TRUE)
})

test_that("the spec resolves the noise model once, with each output's segments", {
  withr::local_seed(1)
  d <- random_grid_data(n = 40, runs = 8, extra = 2)
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * c(0:19, 22:41)
  d$names$period <- "time"
  spec <- bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "additive")
  expect_true(bayesbem:::is_ar1(spec))
  # a gap of two hours starts a second segment
  expect_equal(spec$segments, list(rep(1:2, each = 20)))
  white <- bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "additive",
                                          noise_correlation = "none")
  expect_false(bayesbem:::is_ar1(white))
  expect_null(white$segments)
  # the Stan data read the spec's segments: one segment count per output
  stage1 <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                 b = numeric(sum(bayesbem:::mean_selection(koh_priors(), d$p, d$q))),
                 basis = bayesbem:::basis_emulator(d, variance = 0.99))
  sd <- bayesbem:::basis_stan_data(d, koh_priors(), stage1, bayesbem:::hsgp_design(),
                                   spec$segments)
  expect_equal(c(sd$ar, sd$n_seg), c(1, 2))
})

test_that("the spec resolves a shift per month for meter data over three months or more", {
  withr::local_seed(1)
  d <- random_grid_data(n = 40, runs = 8, extra = 2)
  # a row every other day from 20 June to 6 September: four months
  d$field$time <- as.Date("2013-06-20") + 0:39 * 2
  d$names$period <- "time"
  spec <- bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "additive")
  expect_true(bayesbem:::has_shifts(spec))
  expect_equal(spec$shifts, list(format(d$field$time, "%Y-%m")))
  # two months: no shift unless asked
  two <- d
  two$field$time <- as.Date("2013-07-01") + 0:39
  expect_false(bayesbem:::has_shifts(bayesbem:::calibration_spec_of(two, NULL, discrepancy_kernel = "additive")))
  asked <- bayesbem:::calibration_spec_of(two, NULL, discrepancy_kernel = "additive",
                                          noise_shift = "month")
  expect_equal(unique(asked$shifts[[1]]), c("2013-07", "2013-08"))
  none <- bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "additive", noise_shift = "none")
  expect_false(bayesbem:::has_shifts(none))
  expect_null(none$shifts)
  # the product kernel has none, and refuses one
  expect_false(bayesbem:::has_shifts(bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "product")))
  expect_error(bayesbem:::calibration_spec_of(d, NULL, discrepancy_kernel = "product",
                                              noise_shift = "month"),
               class = "bayesbem_error_argument")
  # the Stan data: one column per month
  stage1 <- list(beta_eta = rep(1, d$p + d$q), lambda_eta = 1,
                 b = numeric(sum(bayesbem:::mean_selection(koh_priors(), d$p, d$q))),
                 basis = bayesbem:::basis_emulator(d, variance = 0.99))
  sd <- bayesbem:::basis_stan_data(d, koh_priors(), stage1, bayesbem:::hsgp_design(),
                                   spec$segments, spec$shifts)
  expect_equal(sd$n_shift, 4L)
  expect_equal(bayesbem:::basis_u_sizes(sd)[["lambda_shift"]], 1)
})

test_that("the additive discrepancy needs the basis emulator and periods of one length", {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  expect_identical(bayesbem:::choose_discrepancy_kernel("additive", "basis", d), "additive")
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", d), "product")
  # "auto", with the basis emulator and equal periods: the kernel whose fit
  # costs less, each at its default iterations, seconds per gradient times
  # the cube of what it factors (fit_cost): the product's n rows against
  # the additive one's 40 basis functions per input (two here) and 10
  # components
  cost <- bayesbem:::fit_cost$seconds_per_cubed_row
  iter <- function(kernel) bayesbem:::default_sampling(TRUE, 500L, "basis", kernel)$iter
  crossover <- (40 * 2 + 10) *
    (iter("additive") * cost[["additive"]] / (iter("product") * cost[["stage2"]]))^(1 / 3)
  below <- random_grid_data(n = floor(crossover) - 2, runs = 3)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", below), "product")
  above <- random_grid_data(n = ceiling(crossover) + 2, runs = 3)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", above), "additive")
  big <- random_grid_data(n = 401, runs = 3)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "separable", big), "product")
  bills <- random_grid_data(n = 401, runs = 3, days = TRUE)
  expect_identical(bayesbem:::choose_discrepancy_kernel("auto", "basis", bills), "product")
  expect_error(bayesbem:::choose_discrepancy_kernel("additive", "separable", d),
               class = "bayesbem_error_argument")
  periods <- random_grid_data(n = 9, runs = 8, extra = 2, days = TRUE)
  expect_error(bayesbem:::choose_discrepancy_kernel("additive", "basis", periods),
               class = "bayesbem_error_argument")
  expect_snapshot(calibrate(d, emulator = "separable", discrepancy_kernel = "additive"), error = TRUE)
})

test_that("AR(1) noise needs the additive discrepancy and the rows' times", {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  choose <- bayesbem:::choose_noise_correlation
  expect_identical(choose("auto", "additive", d), "none")
  expect_identical(choose("none", "additive", d), "none")
  expect_error(choose("ar1", "product", d), class = "bayesbem_error_argument")
  # the rows' times are read where the spec finds the noise's segments, before sampling
  expect_error(bayesbem:::output_segments(d), class = "bayesbem_error_argument")
  expect_snapshot(calibrate(d, emulator = "basis", discrepancy_kernel = "additive",
                            noise_correlation = "ar1"), error = TRUE)
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * 0:8
  d$names$period <- "time"
  expect_identical(choose("ar1", "additive", d), "ar1")
  # "auto": AR(1) where it applies, on consecutive hours with the additive
  # discrepancy; not with the exact one, nor on rows none of which follow
  # another
  expect_identical(choose("auto", "additive", d), "ar1")
  expect_identical(choose("auto", "product", d), "none")
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * c(0, 2, 5, 9, 14, 20, 27, 35, 44)
  expect_identical(choose("auto", "additive", d), "none")
})
