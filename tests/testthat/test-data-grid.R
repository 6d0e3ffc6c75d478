test_that("the shipped design is a grid, in any row order", {
  d <- koh_data(seb_field, seb_sim)
  expect_equal(d$grid$n, 12)
  expect_equal(d$grid$mt, 10)
  # index[i, a] is the simulation row of run a at field input i
  expect_equal(d$xc[d$grid$index[, 3], ], d$xf, ignore_attr = TRUE)
  expect_equal(d$tc[d$grid$index[5, ], ], d$grid$design)
  withr::local_seed(1)
  shuffled <- koh_data(seb_field, seb_sim[sample(120), ])
  # the same outputs per (field input, run), runs numbered by first appearance
  by_run <- function(x) {
    e <- matrix(x$eta[x$grid$index], 12)
    e[, order(x$grid$design[, 1])]
  }
  expect_equal(by_run(shuffled), by_run(d))
})

test_that("runs at further inputs (held-out periods) still form a grid", {
  d <- koh_data(seb_field[-c(3, 8), ], seb_sim)
  expect_equal(c(d$grid$n, d$grid$n_x, d$grid$mt), c(10, 12, 10))
  # field inputs first, then the further ones
  expect_equal(d$grid$x[1:10, ], d$xf, ignore_attr = TRUE)
  expect_equal(d$xc, d$grid$x[d$grid$period, ])
  expect_equal(bayesbem:::choose_structure(d, "auto"), "grid")
})

test_that("incomplete grids are not grids", {
  expect_null(koh_data(seb_field, seb_sim[-7, ])$grid)
  moved <- seb_sim
  moved$temp[1] <- moved$temp[1] + 0.01
  expect_null(koh_data(seb_field, moved, grid_tol = 1e-6)$grid)
  # by default that close is matched, with a message; far is not
  expect_message(near <- koh_data(seb_field, moved), class = "bayesbem_message_near_grid")
  expect_false(is.null(near$grid))
  moved$temp[1] <- moved$temp[1] + 5
  expect_null(koh_data(seb_field, moved)$grid)
})

test_that("periods sharing their inputs share a grid input, each run's outputs there averaged", {
  withr::local_seed(5)
  # field rows 1 and 3 share their inputs (two calm night hours)
  x <- data.frame(a = c(0.1, 0.5, 0.1, 0.9, 0.3), b = c(1, 2, 1, 3, 2))
  sim <- do.call(rbind, lapply(1:4, function(r) data.frame(eta = rnorm(5, 5), x, k = r)))
  field <- data.frame(y = rnorm(5, 5), x)
  expect_message(d <- koh_data(field, sim[sample(20), ]), class = "bayesbem_message_shared_inputs")
  expect_equal(c(d$n, d$m, d$grid$n, d$grid$n_x, d$grid$mt), c(5, 16, 4, 4, 4))
  expect_equal(d$grid$field, c(1, 2, 1, 3, 4))
  runs <- bayesbem:::grid_runs(d) * d$scaling$y_scale + d$scaling$y_center
  for (a in 1:4) {
    run <- d$sim$k[d$grid$index[1, a]]
    expect_equal(runs[1, a], mean(sim$eta[sim$k == run & sim$a == 0.1]))
  }
  # the grid and dense programs, and the R conditionals, agree
  priors <- koh_priors(nugget = 1e-4)
  dense <- bayesbem:::koh_stan_data(d, priors, structure = "dense")
  grid <- bayesbem:::koh_stan_data(d, priors, structure = "grid")
  g_dense <- bayesbem:::gp_geometry(d, NULL, "dense")
  g_grid <- bayesbem:::gp_geometry(d, NULL, "grid")
  for (i in 1:3) {
    pars <- random_koh_pars(dense)
    lp <- stan_log_density(koh_model_for(dense), pars)
    expect_equal(stan_log_density(koh_model_for(grid), pars[names(pars) != "y_pred"]),
                 lp, tolerance = 1e-8)
    expect_equal(reference_log_density(dense, pars), lp, tolerance = 1e-8)
    par <- as_draw_pars(pars, priors$nugget, dense)
    at_grid <- bayesbem:::field_given_runs(bayesbem:::residual_geometry(g_grid, par), par)
    at_dense <- bayesbem:::field_given_runs(bayesbem:::residual_geometry(g_dense, par), par)
    expect_equal(at_grid[c("mean", "cov")], at_dense[c("mean", "cov")], tolerance = 1e-8,
                 ignore_attr = TRUE)
  }
  # the case study with February's weather set to January's: a grid still
  seb <- seb_field
  seb[2, c("temp", "rh", "solar")] <- seb[1, c("temp", "rh", "solar")]
  expect_equal(koh_data(seb, seb_sim)$grid$field[1:3], c(1, 1, 2))
  # a run repeated beyond the field's periods is an error
  expect_error(koh_data(field, rbind(sim, sim[1, ])), class = "bayesbem_error_duplicated")
  # a simulator's periods pair with field rows sharing inputs in order
  expect_equal(bayesbem:::match_in_order(c("a", "b", "a", "c"), c("b", "a", "a")), c(2, 1, 3, NA))
})

test_that("the likelihood structure is chosen automatically or forced", {
  d <- koh_data(seb_field, seb_sim)
  expect_equal(bayesbem:::choose_structure(d, "auto"), "grid")
  expect_equal(bayesbem:::choose_structure(d, "dense"), "dense")
  expect_equal(bayesbem:::choose_structure(d, "auto", predict_at = seb_field[1, 2:4]), "dense")
  not_grid <- koh_data(seb_field, seb_sim[-7, ])
  expect_equal(bayesbem:::choose_structure(not_grid, "auto"), "dense")
  expect_error(calibrate(not_grid, structure = "grid"), class = "bayesbem_error_argument")
  expect_snapshot(calibrate(not_grid, structure = "grid"), error = TRUE)
  expect_snapshot(calibrate(d, structure = "grid", predict_at = seb_field[1, 2:4]), error = TRUE)
})

test_that("runs within 5 % of the field inputs are matched, with a message", {
  sim <- bem_simulator(shipped_epw(2013))
  runs <- simulate_design(sim, design_lhs(bem_parameters()[12:13, ], n = 4, seed = 3))
  # seb_field's solar radiation differs from the weather file's by up to
  # 4.6 W/m2, 3.6 % of its range
  gap <- max(abs(seb_field$solar - sim$x$solar)) / diff(range(seb_field$solar, sim$x$solar))
  expect_gt(gap, 0.01)
  expect_lt(gap, 0.05)
  expect_message(d <- koh_data(seb_field, runs), class = "bayesbem_message_near_grid")
  expect_false(is.null(d$grid))
  expect_equal(d$grid$max_diff, gap, tolerance = 1e-6)
  # the runs' inputs are taken as the field's
  expect_equal(d$xc[d$grid$index[, 1], ], d$xf)
  expect_output(print(d), "the grid likelihood in two stages")
  # exact matching only: the dense likelihood, said when fitting
  d0 <- koh_data(seb_field, runs, grid_tol = 0)
  expect_null(d0$grid)
  expect_output(print(d0), "the dense joint likelihood")
  # 30 runs of 12 months: about an hour per chain
  expect_message(bayesbem:::inform_dense(list(n = 12, m = 360), "dense", "auto"),
                 "about 1 hour", class = "bayesbem_message_dense")
  expect_silent(bayesbem:::inform_dense(list(n = 12, m = 360), "dense", "dense"))
  expect_silent(bayesbem:::inform_dense(d0, "dense", "auto"))
  expect_error(koh_data(seb_field, runs, grid_tol = "a"), class = "bayesbem_error_argument")
})
