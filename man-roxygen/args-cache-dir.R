#' @param cache_dir Optional directory for cached simulator runs, see
#'   [simulate_design()].
