#' @param total On a fit on several outputs, optional weights by output
#'   (`c(electricity = 1, gas = 1)` for site energy, or prices for cost) of
#'   a total computed draw by draw.
