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

test_that("incomplete grids and repeated field inputs are not grids", {
  expect_null(koh_data(seb_field, seb_sim[-7, ])$grid)
  moved <- seb_sim
  moved$temp[1] <- moved$temp[1] + 0.01
  expect_null(koh_data(seb_field, moved, grid_tol = 1e-6)$grid)
  # by default that close is matched, with a message; far is not
  expect_message(near <- koh_data(seb_field, moved), class = "bayesbem_message_near_grid")
  expect_false(is.null(near$grid))
  moved$temp[1] <- moved$temp[1] + 5
  expect_null(koh_data(seb_field, moved)$grid)
  field <- seb_field
  field[2, c("temp", "rh", "solar")] <- field[1, c("temp", "rh", "solar")]
  expect_null(koh_data(field, seb_sim)$grid)
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
