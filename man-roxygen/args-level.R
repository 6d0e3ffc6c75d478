#' @param level Probability of the central intervals (`0.9`: from the 5 %
#'   to the 95 % quantile of the draws).
