#' bayesbem: Bayesian calibration of building energy models with Stan
#'
#' bayesbem implements the Kennedy-O'Hagan (KOH) calibration framework as used
#' by Chong and Menberg (2018) for building energy models: a Gaussian-process
#' emulator of the simulator, a Gaussian-process model discrepancy, the
#' paper's priors, and sampling with Stan's NUTS.
#'
#' The workflow:
#' 1. prepare field and simulation data with [koh_data()];
#' 2. choose priors with [koh_priors()] (and [prior_strength()] for the paper's
#'    three levels);
#' 3. calibrate with [calibrate()], which returns a `bayesbem_fit`;
#' 4. inspect it with `print()`, `summary()` and [posterior::as_draws()].
#'
#' [run_case_study()] runs the whole calibration on the shipped case study
#' ([seb_field], [seb_sim]).
#'
#' @references
#' Chong, A. and Menberg, K. (2018). Guidelines for the Bayesian calibration
#' of building energy models. *Energy and Buildings* 174, 527-547.
#' \doi{10.1016/j.enbuild.2018.06.028}
#'
#' Kennedy, M. C. and O'Hagan, A. (2001). Bayesian calibration of computer
#' models. *Journal of the Royal Statistical Society B* 63(3), 425-464.
#'
#' @keywords internal
#' @name bayesbem-package
#' @aliases bayesbem
#' @useDynLib bayesbem, .registration = TRUE
#' @import methods
#' @import Rcpp
#' @importFrom rstan sampling
#' @importFrom RcppParallel RcppParallelLibs
#' @importFrom rlang %||% .data
#' @importFrom rstantools rstan_config
#' @importFrom parallel detectCores
"_PACKAGE"
