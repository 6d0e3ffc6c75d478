# predict(): calibrated predictions of a fit, of one output or several.

#' Calibrated predictions of a KOH fit
#'
#' Predicts at new observable inputs, in physical units:
#' * `type = "y"`: the calibrated prediction `eta(x, tf) + delta(x)`, plus
#'   observation noise when `noise = TRUE`;
#' * `type = "eta"`: the simulator part `eta(x, tf)` alone (the emulator at
#'   the calibrated parameters);
#' * `type = "delta"`: the model discrepancy `delta(x)` alone (with the
#'   parametric terms of [extend()], when the fit has any).
#'
#' With `method = "conditional"` (the default), each posterior draw of `tf`
#' and the hyperparameters gives the exact Gaussian conditional of
#' `(eta, delta)` at the new inputs given all field and simulation data
#' (mean `S21 S11^-1 z`, covariance `S22 - S21 S11^-1 S12`, one Cholesky
#' factor per draw; for grid designs, see [calibrate()], factors of the run
#' and field-input correlations instead, so the cost grows as O(mt^3 + n^3)),
#' from which one joint sample is drawn; so for every draw
#' the `"y"` value is exactly the `"eta"` value plus the `"delta"` value
#' (plus noise). Sampling uses R's random number generator: call
#' [set.seed()] first for reproducible draws.
#'
#' A fit with the additive discrepancy (`calibrate(discrepancy_kernel =)`)
#' conditions as its likelihood does, at a cost linear in the rows: the
#' basis emulator's weights and the discrepancy's basis coefficients given
#' the data, per draw. Its emulator is the runs at the field rows, so
#' `"y"` and `"eta"` are for field rows' inputs only (elsewhere, run the
#' simulator with [predict_scenario()]); `"delta"` is for any inputs. With
#' AR(1) noise, `noise = TRUE` draws it over `newdata`'s periods (its
#' period column, or the field rows').
#'
#' With `method = "sampled"`, the predictions sampled inside Stan are
#' returned (the paper's Appendix D): they exist only for the inputs given to
#' [calibrate()] as `predict_at`, and include observation noise.
#'
#' @param object A `bayesbem_fit`.
#' @param newdata A data frame with the observable inputs (the field inputs'
#'   column names), and the covariates of any discrepancy terms (see
#'   [extend()]); defaults to the field inputs. Inputs outside the range
#'   the model was calibrated on get a warning (extrapolation).
#' @param type One of `"y"`, `"eta"` or `"delta"`.
#' @template args-ndraws
#' @param summary If `TRUE`, a data frame of summaries; if `FALSE`, a matrix
#'   of draws (rows) by points (columns).
#' @param noise Add observation noise `N(0, 1/lambda_e)` to `type = "y"`.
#' @param method `"conditional"` or `"sampled"` (see Details).
#' @template args-level
#' @template args-total
#' @param ... Unused.
#' @section Several outputs: On a fit on several outputs, every output is
#'   predicted from the same posterior draws. `newdata` is then a data frame
#'   for every output, or a long one whose output column (the column the
#'   data named outputs by) says which output each row is for; by default
#'   each output's field inputs. `total` adds the rows of output `"total"`,
#'   the weighted sum of the outputs draw by draw (needs the same inputs
#'   for every output it adds).
#' @return A data frame with the inputs, `mean`, `sd`, the median `q50` and
#'   the interval's bounds (`q5` and `q95` at `level = 0.9`), or a
#'   draws-by-points matrix. On several outputs, the data frame has a first
#'   column `output`, and the draws are a list of matrices by output (and
#'   `total`).
#' @family prediction
#' @export
#' @examples
#' predict(seb_fit, ndraws = 100)
#' predict(seb_fit, type = "delta", ndraws = 100)
#' predict(seb_fit, data.frame(temp = 15, rh = 45, solar = 250), type = "eta", ndraws = 100)
predict.bayesbem_fit <- function(object, newdata = NULL, type = c("y", "eta", "delta"),
                            ndraws = NULL, summary = TRUE, noise = FALSE,
                            method = c("conditional", "sampled"),
                            level = 0.9, total = NULL, ...) {
  rlang::check_dots_empty()
  type <- match_choice(type)
  method <- match_choice(method)
  check_bool(summary)
  check_bool(noise)
  check_no_total(total)
  if (method == "sampled") {
    draws <- sampled_predictions(object, newdata, type)
    newdata <- object$predict_at
  } else {
    newdata <- newdata %||% field_inputs(object$data)
    draws <- predict_draws(object, newdata, ndraws = ndraws, noise = noise, types = type)[[type]]
  }
  if (!summary) {
    return(draws)
  }
  summarise_columns(draws, newdata[object$data$names$x], level)
}
