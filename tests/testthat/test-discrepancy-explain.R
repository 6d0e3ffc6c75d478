# Candidates: the three inputs, the external covariate, the step, and two
# decoys correlated with the inputs.
synthetic_causes <- c(input = "rh", covariate = "occupancy", step = "after_change")

test_that("each hidden effect is flagged and its cause ranks first", {
  skip_on_cran()
  for (kind in names(synthetic_causes)) {
    case <- synthetic_case(kind)
    expect_true(any(discrepancy(case$base)$flag), label = kind)
    ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 500, regions = FALSE,
                              seed = 1)
    expect_s3_class(ex, "bayesbem_explanation")
    expect_gte(nrow(ex), 4)
    expect_equal(ex$candidate[1], synthetic_causes[[kind]], label = kind)
    expect_true(ex$explains[1], label = kind)
    expect_match(attr(ex, "verdict"), synthetic_causes[[kind]])
  }
})

test_that("an effect in part of another input's range is named with both inputs", {
  skip_on_cran()
  # occupancy costs energy only where temp > 15: the region term, its cut
  # refined into the gap of the fitted months' temperatures that holds 15,
  # explains nearly all of the residual
  case <- synthetic_case("interaction")
  ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 500, seed = 1)
  expect_match(ex$candidate[1], "^occupancy, where temp > ")
  temp <- case$field$temp[-synthetic_held_out]
  cut <- bayesbem:::parse_region(ex$candidate[1])$cut
  expect_true(cut > max(temp[temp <= 15]) && cut < min(temp[temp > 15]))
  expect_true(ex$explains[1])
  expect_gt(ex$share[1], 0.7)
  expect_match(attr(ex, "verdict"), ex$candidate[1], fixed = TRUE)
})

test_that("a region beyond chance is cross-validated as the term it is named as", {
  skip_on_cran()
  # recomputed from the posterior mean residual and the recalibration
  # basis: every region beyond chance, named or not, carries its named
  # (refined) term's cv_gain, and explains exactly when that is positive
  case <- synthetic_case("interaction")
  ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 500, seed = 1)
  rg <- bayesbem:::recalibration_geometry(case$base)
  table <- cbind(case$base$data$field[case$base$data$names$x], case$train_covariates)
  region <- !ex$candidate %in% names(table) & ex$p_value < 0.05
  expect_gte(sum(region), 1)
  for (i in which(region)) {
    term <- bayesbem:::term_matrix(ex$candidate[i], table)
    gain <- bayesbem:::cv_gain(colMeans(rg$given_runs$residual), rg$basis, term,
                               line = bayesbem:::is_line(ex$candidate[i]))
    expect_equal(ex$cv_gain[i], gain, tolerance = 1e-8, label = ex$candidate[i])
    expect_identical(ex$explains[i], gain > 0)
  }
})

test_that("a correct simulator gets no cause in the large majority of data draws", {
  skip_on_cran()
  # four noise draws of data without a hidden effect, regions included;
  # with alpha = 0.05 family-wise, two or more alarms in four draws has
  # probability ~1.4 %
  explanations <- lapply(5:8, function(noise_seed) {
    case <- if (noise_seed == 5) synthetic_case("none") else
      make_synthetic_case("none", noise_seed = noise_seed)
    explain_discrepancy(case$base, case$train_covariates, n_null = 500, seed = 1)
  })
  alarms <- vapply(explanations, function(ex) any(ex$explains), logical(1))
  expect_lte(sum(alarms), 1)
  for (ex in explanations[!alarms]) {
    expect_equal(attr(ex, "verdict"), "No candidate explains the discrepancy beyond chance.")
  }
})

test_that("a candidate that only mimics a parameter's effect is not credited", {
  skip_on_cran()
  case <- synthetic_case("step")
  # the direction in which equipment power density moves the output
  sim <- synthetic_simulator()
  p <- stats::setNames(as.list(sim$parameters$initial), sim$parameters$parameter)
  lo <- sim$fun(utils::modifyList(p, list(equipment_power_density = 10)), sim$x)
  hi <- sim$fun(utils::modifyList(p, list(equipment_power_density = 20)), sim$x)
  mimic <- data.frame(epd_effect = (hi - lo)[-synthetic_held_out])
  ex <- explain_discrepancy(case$base, cbind(case$train_covariates, mimic), n_null = 200,
                            seed = 1)
  expect_lt(ex$share[ex$candidate == "epd_effect"], 0.1)
  expect_false(ex$explains[ex$candidate == "epd_effect"])
  expect_equal(ex$candidate[1], "after_change")
})

test_that("shares are fractions with intervals, p-values adjusted", {
  skip_on_cran()
  ex <- explain_discrepancy(shared_fit(), data.frame(k = seq_len(12)), n_null = 100,
                            ndraws = 50, seed = 2)
  expect_named(ex, c("candidate", "share", "lower", "upper", "z", "p_value", "cv_gain", "explains"))
  expect_true(all(ex$lower <= ex$share & ex$share <= ex$upper))
  expect_true(all(ex$share >= 0 & ex$share <= 1))
  expect_true(all(ex$p_value > 0 & ex$p_value <= 1))
  expect_equal(explain_discrepancy(shared_fit(), data.frame(k = seq_len(12)), n_null = 100,
                                   ndraws = 50, seed = 2), ex)
})

test_that("the null keeps the model's structure: residuals given the runs, covariance without delta", {
  fit <- seb_fit
  g <- bayesbem:::gp_geometry(fit$data, NULL, "grid")
  pars <- bayesbem:::draw_parameters(fit, 3)
  par <- pars[[2]]
  out <- bayesbem:::residuals_given_runs(g, list(par))
  # independently, on the dense algebra: y given the runs has mean m and
  # covariance S; without the discrepancy the covariance is S - Sigma_delta
  gd <- bayesbem:::gp_geometry(fit$data, NULL, "dense")
  rg <- bayesbem:::residual_geometry(gd, par)
  sigma <- bayesbem:::koh_sigma_z(rg, par)
  f <- seq_len(12)
  m <- drop(sigma[f, -f] %*% solve(sigma[-f, -f], rg$eta))
  s <- sigma[f, f] - sigma[f, -f] %*% solve(sigma[-f, -f], sigma[-f, f])
  expect_equal(drop(out$residual), rg$y - m, tolerance = 1e-6)
  expect_equal(out$emulator + out$noise, s - bayesbem:::delta_cov(gd$ff, par),
               tolerance = 1e-6)
  # periods of one length, white noise: every row has the noise 1 / lambda_e
  expect_equal(out$noise, diag(1 / par$lambda_e, 12), ignore_attr = TRUE)
  # over several draws: each draw's residual, the covariances' means
  each <- lapply(pars, function(p) bayesbem:::residuals_given_runs(g, list(p)))
  all <- bayesbem:::residuals_given_runs(g, pars)
  expect_equal(all$residual, do.call(rbind, lapply(each, `[[`, "residual")))
  expect_equal(all$emulator, Reduce(`+`, lapply(each, `[[`, "emulator")) / 3)
  expect_equal(all$noise, Reduce(`+`, lapply(each, `[[`, "noise")) / 3)
})

test_that("with the basis emulator the null is the basis model's, at linear cost", {
  withr::local_seed(24)
  case <- ar1_basis_case()
  d <- case$data
  basis <- case$basis
  segments <- case$segments
  fit <- structure(list(data = d, emulator = list(basis = basis)), class = "bayesbem_fit")
  g <- bayesbem:::explanation_geometry(fit)
  pars <- lapply(c(0.6, -0.3), function(phi) {
    list(tf = stats::runif(d$q, 0.1, 0.9), rho_delta = rep(0.5, 2), lambda_delta = 1,
         lambda_e = stats::rgamma(1, 10, 0.3), gamma = numeric(0), phi = phi)
  })
  # each draw's mean and covariance without the discrepancy, element by element
  refs <- lapply(pars, function(par) {
    reference_basis(case$sd, basis, par, function(...) 0, reference_ar1_cor(par$phi, segments))
  })
  given_runs <- bayesbem:::residuals_given_runs(g, pars)
  expect_equal(given_runs$residual, t(vapply(refs, function(r) d$y - r$mean, numeric(9))),
               tolerance = 1e-8, ignore_attr = TRUE)
  # the null residuals' covariance is the draws' mean one (Monte Carlo, 40,000)
  null <- bayesbem:::null_residuals(g, pars, given_runs, kappa = 1, n_null = 40000)
  expected <- (refs[[1]]$cov + refs[[2]]$cov) / 2
  expect_lt(max(abs(stats::cov(t(null)) - expected)) / max(diag(expected)), 0.03)
  # the emulator's part is inflated by kappa: components and truncated rest
  emulator <- expected - Reduce(`+`, lapply(pars, function(par) {
    reference_ar1_cor(par$phi, segments) / par$lambda_e
  })) / 2
  inflated <- bayesbem:::null_residuals(g, pars, given_runs, kappa = 3, n_null = 40000)
  expect_lt(max(abs(stats::cov(t(inflated)) - expected - 2 * emulator)) / max(diag(expected)),
            0.05)
})

test_that("the basis emulator's inflation is its components' cross-validated error", {
  withr::local_seed(25)
  d <- random_grid_data(n = 9, runs = 12, extra = 2)
  basis <- bayesbem:::basis_emulator(d, variance = 0.99)
  h <- cbind(1, basis$tc)
  fold <- (seq_len(12) - 1) %% 10 + 1
  # each run's weight predicted by its component refitted without the run's
  # fold, by the kriging equations with the refitted mean's coefficients
  z2 <- unlist(lapply(seq_along(basis$components), function(j) {
    unlist(lapply(1:10, function(f) {
      out <- fold == f
      gp <- bayesbem:::fit_component(basis$tc[!out, , drop = FALSE], basis$w[!out, j])
      scaled <- sweep(basis$tc, 2, sqrt(gp$beta), "*")
      k <- gp$s2 * (exp(-as.matrix(stats::dist(scaled))^2) + diag(gp$nug, 12))
      r <- basis$w[!out, j] - drop(h[!out, ] %*% gp$b)
      vapply(which(out), function(a) {
        m <- sum(h[a, ] * gp$b) + sum(k[a, !out] * solve(k[!out, !out], r))
        v <- k[a, a] - sum(k[a, !out] * solve(k[!out, !out], k[!out, a]))
        (basis$w[a, j] - m)^2 / v
      }, numeric(1))
    }))
  }))
  expect_length(z2, 12 * length(basis$components))
  g <- list(basis = basis)
  expect_equal(bayesbem:::emulator_inflation(g, list()), max(1, mean(z2)), tolerance = 1e-6)
})

test_that("a share's interval is the jackknife over blocks of periods, not the draws' spread", {
  withr::local_seed(8)
  n <- 27
  # blocks of round(27^(1/3)) = 3 consecutive periods
  basis <- cbind(1, stats::rnorm(n))
  r <- stats::rnorm(n)
  blocks <- bayesbem:::jackknife_blocks(basis, r)
  expect_length(blocks, 9)
  expect_equal(setdiff(seq_len(n), blocks[[2]]$rows), 4:6)
  # without block 2, the share is the partial R^2 of lm() on the rows left
  b <- cbind(stats::rnorm(n))
  rows <- blocks[[2]]$rows
  reduced <- stats::lm(r[rows] ~ basis[rows, 2])
  full <- stats::lm(r[rows] ~ basis[rows, 2] + b[rows, 1])
  partial <- 1 - sum(stats::residuals(full)^2) / sum(stats::residuals(reduced)^2)
  residual <- matrix(r, 1)
  q <- qr(basis)
  free <- qr.resid(q, t(residual))
  s <- bayesbem:::term_scores(b, free, drop(free), qr.resid(q, matrix(stats::rnorm(n * 5), n)),
                              q, 0.9, blocks)
  left_out <- vapply(blocks, function(k) {
    rss <- function(fit) sum(stats::residuals(fit)^2)
    1 - rss(stats::lm(r[k$rows] ~ basis[k$rows, 2] + b[k$rows, 1])) /
      rss(stats::lm(r[k$rows] ~ basis[k$rows, 2]))
  }, numeric(1))
  expect_equal(left_out[[2]], partial)
  se <- sqrt(8 / 9 * sum((left_out - mean(left_out))^2))
  expect_equal(unlist(s$summary[c("lower", "upper")]),
               pmin(pmax(s$summary$share + c(-1, 1) * stats::qnorm(0.95) * se, 0), 1),
               ignore_attr = TRUE)
  # on the shipped fit the interval is an interval, not the share again
  ex <- explain_discrepancy(seb_fit, n_null = 100, ndraws = 20, regions = FALSE, seed = 1)
  expect_true(all(ex$upper - ex$lower > 0.02))
  expect_true(all(ex$lower <= ex$share & ex$share <= ex$upper))
  expect_match(attr(ex, "verdict"), "interval over left-out periods|No candidate")
})

test_that("partial R^2 of many residuals is lm()'s, with or without their kept totals", {
  withr::local_seed(5)
  n <- 60
  nuisance <- qr(cbind(1, stats::rnorm(n)))
  r <- qr.resid(nuisance, matrix(stats::rnorm(n * 3), n))
  b <- cbind(stats::rnorm(n), stats::runif(n))
  x <- qr.X(nuisance)
  by_lm <- apply(r, 2, function(y) {
    rss <- function(fit) sum(stats::residuals(fit)^2)
    1 - rss(stats::lm(y ~ x + b - 1)) / rss(stats::lm(y ~ x - 1))
  })
  expect_equal(bayesbem:::partial_r_squared(b, r, nuisance), by_lm)
  expect_equal(bayesbem:::partial_r_squared(b, bayesbem:::with_totals(r), nuisance), by_lm)
})

test_that("recalibration removes the output's curvature in the parameters", {
  # eta draws exactly quadratic in tf: nothing is left after projection
  tf <- withr::with_seed(1, matrix(stats::rnorm(400), 200))
  x <- seq(0, 1, length.out = 30)
  eta <- outer(tf[, 1], sin(3 * x)) + outer(tf[, 2], x) + outer(tf[, 1]^2, (x > 0.5) * 1) +
    outer(tf[, 1] * tf[, 2], x^2)
  basis <- bayesbem:::recalibration_basis(eta, tf)
  expect_equal(dim(basis), c(30, 6))
  centred <- sweep(eta, 2, colMeans(eta))
  expect_lt(max(abs(qr.resid(qr(basis), t(centred)))), 1e-8)
  # the linear part alone leaves the step at x = 0.5
  linear <- qr(basis[, 1:3])
  expect_gt(max(abs(qr.resid(linear, t(centred)))), 0.1)
  # at most n / 3 columns, never fewer than the linear ones
  expect_equal(ncol(bayesbem:::recalibration_basis(eta[, 1:12], tf)), 4)
  expect_equal(ncol(bayesbem:::recalibration_basis(eta[, 1:6], tf)), 3)
})

test_that("the emulator's inflation is the same on the grid and on the dense algebra", {
  pars <- bayesbem:::draw_parameters(seb_fit, 4)
  grid <- bayesbem:::emulator_inflation(bayesbem:::gp_geometry(seb_fit$data, NULL, "grid"), pars)
  dense <- bayesbem:::emulator_inflation(bayesbem:::gp_geometry(seb_fit$data, NULL, "dense"), pars)
  expect_equal(grid, dense, tolerance = 1e-6)
  expect_gte(grid, 1)
})

test_that("regions name an effect that acts in part of another input's range", {
  ex <- explain_discrepancy(seb_fit, ndraws = 50, n_null = 200, seed = 1)
  expect_true(any(grepl("^solar, where temp < ", ex$candidate)))
  expect_true(any(grepl("^temp > ", ex$candidate)))
  # every observable input is a candidate, with and without regions
  expect_true(all(c("temp", "rh", "solar") %in% ex$candidate))
  expect_lt(sum(ex$explains), nrow(ex))
})

test_that("p-values are adjusted within each family and share alpha across families", {
  # two main terms and one region, five null residuals each
  score <- function(z, null_z) list(summary = data.frame(z = z), null_z = null_z)
  scores <- list(score(3, c(0, 1, 2, 4, -1)), score(1, c(1, 0, 0, 0, 5)),
                 score(3.5, c(0, 3, 0, 0, 0)))
  p <- bayesbem:::adjusted_p_values(scores, c("main", "main", "region"),
                                    c(main = 0.8, region = 0.2))
  # main family maxima 1, 1, 2, 4, 5: z = 3 is reached by two, z = 1 by all
  # five; the region's own null never reaches 3.5
  expect_equal(p, c((1 + 2) / 6 / 0.8, 1, (1 + 0) / 6 / 0.2))
  # one family: the plain Westfall-Young adjustment
  expect_equal(bayesbem:::adjusted_p_values(scores[1:2], c("main", "main"), c(main = 1)),
               c(3 / 6, 1))
})

test_that("bad candidates get classed errors", {
  expect_error(explain_discrepancy(seb_fit, data.frame(k = 1:5)),
               class = "bayesbem_error_covariates")
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(k = 1:5)), error = TRUE)
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(temp = 1:12)), error = TRUE)
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(flat = rep(1, 12))), error = TRUE)
  expect_error(explain_discrepancy(seb_fit, alpha = 2), class = "bayesbem_error_argument")
  # Too few null residuals for any region (p >= 1 / 100 / 0.2) or any term to pass alpha.
  expect_snapshot(explain_discrepancy(seb_fit, n_null = 99), error = TRUE)
  expect_snapshot(explain_discrepancy(seb_fit, n_null = 18, regions = FALSE), error = TRUE)
  expect_s3_class(explain_discrepancy(seb_fit, n_null = 20, regions = FALSE, ndraws = 20, seed = 1),
                  "bayesbem_explanation")
})

test_that("cv_gain is the leave-one-out gain of a term, refitted row by row", {
  withr::local_seed(3)
  n <- 20
  basis <- cbind(1, stats::rnorm(n))
  b <- stats::rnorm(n)
  r <- drop(basis %*% c(1, 2)) + 0.8 * b + stats::rnorm(n, sd = 0.3)
  press <- function(x) {
    sum(vapply(seq_len(n), function(i) {
      coef <- stats::lm.fit(x[-i, , drop = FALSE], r[-i])$coefficients
      (r[i] - sum(x[i, ] * coef))^2
    }, numeric(1)))
  }
  expect_equal(bayesbem:::cv_gain(r, basis, b), 1 - press(cbind(basis, b)) / press(basis))
  expect_gt(bayesbem:::cv_gain(r, basis, b), 0)
  # a term that only fits noise predicts left-out rows worse
  noise <- stats::rnorm(n)
  expect_lt(bayesbem:::cv_gain(drop(basis %*% c(1, 2)) + stats::rnorm(n, sd = 0.3), basis, noise), 0.05)
  # a term that fits a single row cannot predict it
  expect_equal(bayesbem:::cv_gain(r, basis, as.numeric(seq_len(n) == 4)), -Inf)
})

test_that("two causes that explain the same residual give the ambiguous verdict", {
  skip_on_cran()
  case <- synthetic_case("covariate")
  # a second record of the same events in other units (hours booked), another cause by name
  bookings <- data.frame(bookings = 8 * case$train_covariates$occupancy + 1)
  ex <- explain_discrepancy(case$base, cbind(case$train_covariates, bookings), n_null = 500,
                            regions = FALSE, seed = 1)
  expect_true(ex$explains[1])
  expect_setequal(c(ex$candidate[1], attr(ex, "ambiguous")), c("occupancy", "bookings"))
  expect_match(attr(ex, "verdict"), "ambiguously between")
  # without the copy the same fit names occupancy alone
  plain <- explain_discrepancy(case$base, case$train_covariates, n_null = 500, regions = FALSE,
                               seed = 1)
  expect_equal(attr(plain, "ambiguous"), character(0))
  expect_match(attr(plain, "verdict"), "best explained by occupancy")
})

test_that("the verdict names the first cause and at most five others, each candidate once", {
  table <- data.frame(candidate = c("hour, where weekend > 0.5", "hour, where temp > 20",
                                    "solar", "temp", "rh", "weekend", "occupancy", "weekday",
                                    "decoy"),
                      share = seq(0.5, 0.1, length.out = 9), lower = 0, upper = 1, z = 3,
                      p_value = 0.001, cv_gain = 0.1, explains = c(rep(TRUE, 8), FALSE))
  verdict <- bayesbem:::explanation_verdict(table, 0.9)
  expect_match(verdict, "best explained by hour, where weekend > 0.5: 50%", fixed = TRUE)
  # "hour" named again in another region is not another cause
  expect_match(verdict, "(also beyond chance: solar, temp, rh, weekend, occupancy and 1 more in the table).",
               fixed = TRUE)
  expect_no_match(verdict, "decoy")
  three <- bayesbem:::explanation_verdict(table[c(1, 3, 4, 9), ], 0.9)
  expect_match(three, "(also beyond chance: solar, temp).", fixed = TRUE)
})

test_that("on simulated nulls each family of terms holds its share of alpha", {
  # residuals drawn from the null itself (white noise about a constant), 36
  # rows of three inputs: the candidates' family may name a term in 4 % of
  # draws, the regions' in 1 % (0.8 and 0.2 of alpha = 0.05)
  withr::local_seed(8)
  n <- 36
  inputs <- data.frame(temp = stats::runif(n, -5, 25), rh = stats::runif(n, 30, 70),
                       solar = stats::runif(n, 100, 300))
  main <- bayesbem:::main_terms(inputs)
  regions <- bayesbem:::region_terms(inputs, inputs)
  family <- rep(c("main", "region"), c(length(main), length(regions)))
  nuisance <- qr(matrix(1, n))
  null_free <- qr.resid(nuisance, matrix(stats::rnorm(n * 400), n))
  alarms <- vapply(seq_len(100), function(i) {
    r <- matrix(stats::rnorm(n), 1)
    blocks <- bayesbem:::jackknife_blocks(matrix(1, n), drop(r))
    free <- qr.resid(nuisance, t(r))
    scores <- lapply(c(main, regions), function(b) {
      bayesbem:::term_scores(b, free, drop(free), null_free, nuisance, 0.9, blocks)
    })
    p <- bayesbem:::adjusted_p_values(scores, family, bayesbem:::region_weights)
    c(main = any(p[family == "main"] < 0.05), region = any(p[family == "region"] < 0.05))
  }, logical(2))
  expect_gt(length(regions), 50)
  # binomial(100, 0.04) exceeds 10 with probability 0.003; binomial(100, 0.01) exceeds 5 with 0.0006
  expect_lte(sum(alarms["main", ]), 10)
  expect_lte(sum(alarms["region", ]), 5)
})

test_that("an effect in humid months is named as a region of humidity at its edge", {
  skip_on_cran()
  # 250 kWh where rh > 47: with regions, the first cause is a region of rh
  # (the step itself or a nested shape of it), cut in the gap that holds 47
  case <- synthetic_case("input")
  ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 500, seed = 1)
  region <- bayesbem:::parse_region(ex$candidate[1])
  expect_true(ex$explains[1])
  expect_identical(c(region$input, region$side), c("rh", ">"))
  rh <- case$field$rh[-synthetic_held_out]
  expect_true(region$cut > max(rh[rh <= 47]) && region$cut < min(rh[rh > 47]))
})

test_that("a named region's cut moves to the gap where the effect's edge is", {
  # a step of 250 where rh > 47 plus noise, 36 rows: the candidate grid's
  # cuts (quartiles, tertiles, median) miss the gap holding 47; refinement
  # finds it, for the step and for a covariate's effect there
  withr::local_seed(3)
  n <- 36
  table <- data.frame(rh = round(stats::runif(n, 30, 60), 1), occupancy = stats::runif(n))
  gap <- c(max(table$rh[table$rh <= 47]), min(table$rh[table$rh > 47]))
  grid <- bayesbem:::region_cuts(table$rh)
  expect_false(any(grid > gap[1] & grid < gap[2]))
  nearest <- grid[which.min(abs(grid - 47))]
  nuisance <- qr(matrix(1, n))
  for (effect in c("", "occupancy")) {
    size <- if (nzchar(effect)) table$occupancy else 1
    r <- 250 * size * (table$rh > 47) + stats::rnorm(n, sd = 5)
    free <- qr.resid(nuisance, r)
    named <- bayesbem:::region_label(effect, "rh", ">", nearest)
    refined <- bayesbem:::refine_region(named, table, free, nuisance)
    cut <- bayesbem:::parse_region(refined)$cut
    expect_true(cut > gap[1] && cut < gap[2], label = refined)
    expect_identical(bayesbem:::parse_region(refined)$effect, effect)
  }
  # a hinge's cut moves to its kink (within 1.5 units of rh: a kink is less
  # sharp than an edge)
  r <- 8 * pmax(table$rh - 47, 0) + stats::rnorm(n, sd = 5)
  refined <- bayesbem:::refine_region(bayesbem:::hinge_label("rh", ">", nearest), table,
                                      qr.resid(nuisance, r), nuisance)
  expect_lte(abs(bayesbem:::parse_hinge(refined)$cut - 47), 1.5)
  # inputs equal but for rounding have no split a name can state
  close <- data.frame(rh = c(1:10, 10 + 1e-14, 41:50))
  expect_false(grepl("NA", bayesbem:::refine_region("rh > 25.5", close, stats::rnorm(21),
                                                    qr(matrix(1, 21)))))
  # a cut with no other split between its neighbours stays
  expect_identical(bayesbem:::refine_region("rh > 47", data.frame(rh = c(1:5, 50:54)), 1:10,
                                            qr(matrix(1, 10))), "rh > 47")
})

test_that("a region-specific line is named only where it beats its step and its candidate", {
  # 36 rows; a step of 250 where rh > 47, or a line there (100 + 300 x
  # occupancy); null residuals of the noise's sd. The line always explains
  # at least as much as its step: the step is named unless the slope is
  # beyond chance and predicts.
  withr::local_seed(4)
  n <- 36
  table <- data.frame(rh = round(stats::runif(n, 30, 60), 1), occupancy = stats::runif(n),
                      temp = stats::runif(n, -5, 25))
  null <- matrix(stats::rnorm(n * 400, sd = 5), n)
  basis <- matrix(1, n)
  noise <- stats::rnorm(n, sd = 5)
  step <- 250 * (table$rh > 47) + noise
  line <- (100 + 300 * table$occupancy) * (table$rh > 47) + noise
  main <- bayesbem:::main_terms(table)
  labels <- names(bayesbem:::region_terms(table, table))
  null_free <- bayesbem:::with_totals(qr.resid(qr(basis), null))
  simplest <- function(name, r) {
    bayesbem:::simplest_region(name, table, basis, r, null_free, 0.05, main, labels)
  }
  for (effect in c("occupancy", "temp")) {
    named <- simplest(paste0(effect, ", where rh > 47"), step)
    expect_identical(bayesbem:::parse_region(named)$effect, "", label = named)
    expect_identical(bayesbem:::term_variables(named), "rh")
  }
  expect_identical(simplest("occupancy, where rh > 47", line), "occupancy, where rh > 47")
  # an effect of occupancy in every row: the line where rh > 47 holds
  # it there, but beats occupancy alone by no more than chance
  everywhere <- 300 * table$occupancy + noise
  expect_identical(simplest("occupancy, where rh > 47", everywhere), "occupancy")
  # a change that all but one row where rh > 47 come after: its line there
  # differs from the step in that row, and a large residual in it makes
  # the line beat the step beyond chance, but it predicts no left-out row
  wet <- which(table$rh > 47)
  table$after_change <- as.numeric(seq_len(n) >= min(wet[-1]))
  main <- bayesbem:::main_terms(table)
  labels <- names(bayesbem:::region_terms(table, table))
  spike <- step + 60 * (seq_len(n) == wet[1])
  expect_identical(sum(table$after_change[wet] == 0), 1L)
  chances <- bayesbem:::chances_given(list(label = "rh > 47", columns = 1 * (table$rh > 47)),
                                      "after_change, where rh > 47", table, basis, spike,
                                      null_free, new.env())
  expect_gt(chances[[1]]$z, max(chances[[1]]$null_z))
  expect_identical(simplest("after_change, where rh > 47", spike), "rh > 47")
  # steps and hinges are left as they are
  expect_identical(simplest("rh > 47", line), "rh > 47")
  expect_identical(simplest("max(rh - 47, 0)", line), "max(rh - 47, 0)")
  # the lines' scores given a simpler term, from the null residuals
  # projected once, as from the null residuals projected given that term
  alt <- list(label = "occupancy", columns = main$occupancy)
  lines <- c("occupancy, where rh > 47", "temp, where rh > 47", "temp, where rh < 47")
  memo <- new.env()
  kept <- bayesbem:::chances_given(alt, lines, table, basis, line, null_free, memo)
  nuisance <- qr(cbind(basis, alt$columns))
  again <- lapply(lines, function(l) {
    bayesbem:::chance_z(bayesbem:::term_matrix(l, table), qr.resid(nuisance, line),
                        bayesbem:::with_totals(qr.resid(nuisance, null)), nuisance)
  })
  expect_equal(kept, again, tolerance = 1e-10)
  expect_setequal(ls(memo), paste("occupancy", lines, sep = "\r"))
})
