test_that("design_lhs() is a Latin hypercube over the parameter ranges", {
  params <- bem_parameters()[c(3, 12, 14), ]
  d <- design_lhs(params, n = 10, seed = 1)
  expect_named(d, params$parameter)
  expect_equal(nrow(d), 10)
  for (k in seq_along(d)) {
    u <- (d[[k]] - params$min[k]) / (params$max[k] - params$min[k])
    # one point in each of the 10 strata of every column
    expect_equal(sort(floor(u * 10)), 0:9)
  }
  expect_identical(design_lhs(params, n = 10, seed = 1), d)
})

test_that("design_lhs() leaves the caller's random stream alone", {
  set.seed(99)
  before <- runif(1)
  set.seed(99)
  design_lhs(bem_parameters()[1:2, ], n = 5, seed = 3)
  expect_equal(runif(1), before)
})

test_that("bad designs get classed errors", {
  expect_error(design_lhs(bem_parameters()[1:2, ], n = 1), class = "bayesbem_error_argument")
  bad <- bem_parameters()[1:2, ]
  bad$min[2] <- 30
  expect_error(design_lhs(bad, n = 5), class = "bayesbem_error_parameters")
  expect_snapshot(design_lhs(bad, n = 5), error = TRUE)
})
