#' @param covariates For a fit with discrepancy terms ([extend()]): the
#'   values of the covariates they use that the simulator's inputs lack
#'   (e.g. [calendar_covariates()] of the scenario's simulator), a data
#'   frame with one row per period of the scenario; on several outputs, a
#'   list of them named by output.
