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

# The session's generator: its kinds and its .Random.seed (NULL when there
# is none yet).
saved_seed <- function() {
  seed <- if (exists(".Random.seed", envir = globalenv())) get(".Random.seed", envir = globalenv())
  list(kind = RNGkind(), seed = seed)
}

# Puts back a saved generator. The kinds are restored first: without a
# .Random.seed the next draw seeds itself under the current kind, which
# (e.g. after future.apply) may not be the session's.
restore_seed <- function(old) {
  do.call(RNGkind, as.list(old$kind))
  if (!is.null(old$seed)) {
    assign(".Random.seed", old$seed, envir = globalenv())
  } else if (exists(".Random.seed", envir = globalenv())) {
    rm(".Random.seed", envir = globalenv())
  }
}
