#' @param level Probability of the central intervals. From n draws each
#'   interval is the pair of order statistics that holds a new draw with
#'   probability at least `level` (the 2nd and 39th of 40 draws at `0.9`),
#'   where the 5 % and 95 % sample quantiles of a few draws hold less;
#'   fewer than `(1 + level) / (1 - level)` draws (19 at `0.9`) cannot reach
#'   `level`, which is warned.
