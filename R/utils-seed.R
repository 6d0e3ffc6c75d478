# Evaluates `expr` with R's random number generator seeded, restoring the
# caller's generator state afterwards; `seed = NULL` leaves it alone. The
# generator kind is fixed too, so that a seed gives the same numbers whatever
# kind the session uses (future.apply, for one, leaves L'Ecuyer-CMRG set).
with_seed <- function(seed, expr) {
  if (is.null(seed)) {
    return(expr)
  }
  check_count(seed)
  old <- saved_seed()
  on.exit(restore_seed(old))
  set.seed(seed, kind = "Mersenne-Twister", normal.kind = "Inversion", sample.kind = "Rejection")
  expr
}

# The session's .Random.seed, or NULL when there is none yet.
saved_seed <- function() {
  if (exists(".Random.seed", envir = globalenv())) get(".Random.seed", envir = globalenv())
}

# Puts back a saved .Random.seed (NULL: there was none).
restore_seed <- function(old) {
  if (!is.null(old)) {
    assign(".Random.seed", old, envir = globalenv())
  } else if (exists(".Random.seed", envir = globalenv())) {
    rm(".Random.seed", envir = globalenv())
  }
}
