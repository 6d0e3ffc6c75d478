#' @param ndraws Number of posterior draws, evenly spaced over the chains;
#'   `NULL` (the default) uses them all.
