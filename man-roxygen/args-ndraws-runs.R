#' @param ndraws Number of posterior draws, evenly spaced over the chains,
#'   at which the simulator runs (one run per draw and scenario).
