# Evaluates `expr` with R's random number generator seeded, restoring the
# caller's generator state afterwards; `seed = NULL` leaves it alone.
with_seed <- function(seed, expr) {
  if (is.null(seed)) {
    return(expr)
  }
  check_count(seed)
  old <- if (exists(".Random.seed", envir = globalenv())) get(".Random.seed", envir = globalenv())
  on.exit(if (is.null(old)) rm(".Random.seed", envir = globalenv()) else
    assign(".Random.seed", old, envir = globalenv()))
  set.seed(seed)
  expr
}
