# The scale of each calibration parameter (koh_data(scales = )): a named
# character vector with one of names(scale_functions) per column of `t`.
parameter_scales <- function(scales, t, x, eta, call = rlang::caller_env()) {
  params <- colnames(t)
  out <- stats::setNames(rep("identity", length(params)), params)
  if (identical(scales, "auto")) {
    return(auto_scales(t, x, eta))
  }
  if (identical(scales, "identity")) {
    return(out)
  }
  if (!is.character(scales) || is.null(names(scales)) || anyNA(scales) ||
      any(!nzchar(names(scales)))) {
    abort_bayesbem(c("{.arg scales} must be {.val auto}, {.val identity} or a named character vector, not {describe_value(scales)}.",
                     i = "For example {.code c({params[1]} = \"log\")}."),
                   "argument", call = call)
  }
  unknown <- setdiff(names(scales), params)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg scales} names {.field {unknown}}, which {?is not a/are not} calibration parameter{?s}.",
                     i = "The calibration parameters are {.field {params}}."),
                   "argument", call = call)
  }
  bad <- setdiff(scales, names(scale_functions))
  if (length(bad) > 0L) {
    abort_bayesbem(c("{.arg scales} must be {.or {.val {names(scale_functions)}}}, not {.val {bad}}."),
                   "argument", call = call)
  }
  out[names(scales)] <- scales
  not_positive <- params[out != "identity" & apply(t, 2, min) <= 0]
  if (length(not_positive) > 0L) {
    abort_bayesbem(c("{.field {not_positive}} take{?s/} values at or below 0 in {.arg sim}: no log or reciprocal scale.",
                     i = "Only positive parameters have those scales: use {.val identity}."),
                   "argument", call = call)
  }
  out
}

# A positive parameter goes on the log or reciprocal scale when that lowers
# by at least `gain` the error with which the emulator's linear mean (the
# least-squares fit of the runs' output on a constant, the inputs and the
# parameters) predicts each run left out, the other parameters as they are.
# Runs left out rather than residuals: for a parameter whose range reaches
# down to 0 (infiltration), the log or reciprocal scale puts the run
# nearest 0 far from all others, a fit to every run matches that run alone,
# and the emulator then has one run at one end of the scale and the rest at
# the other (inst/notes/decisions/D3-parameter-scales.md).
auto_scales <- function(t, x, eta, gain = 0.2) {
  run <- row_groups(t)
  # every parameter as it is: the same for each parameter's comparison
  identity <- left_out_ss(cbind(1, x, t), eta, run)
  others <- setdiff(names(scale_functions), "identity")
  vapply(stats::setNames(seq_len(ncol(t)), colnames(t)), function(k) {
    if (min(t[, k]) <= 0) {
      return("identity")
    }
    ss <- vapply(others, function(scale) {
      tk <- t
      tk[, k] <- scale_functions[[scale]]$to(t[, k])
      left_out_ss(cbind(1, x, tk), eta, run)
    }, numeric(1))
    best <- names(which.min(ss))
    if (ss[[best]] < (1 - gain) * identity) best else "identity"
  }, character(1))
}

# The sum of squared errors with which the least-squares fit of `y` on `X`
# predicts each group of rows from the other rows. For the rows g of a
# group, the deleted residuals are e_(g) = (I - U U')^-1 e_g (Belsley, Kuh &
# Welsch 1980, sec. 2.1), with e the full fit's residuals and U the rows g of
# an orthonormal basis Q of X's columns (H_gg = U U'); by Woodbury,
# (I - U U')^-1 e_g = e_g + U (I - U'U)^-1 U' e_g, a solve of X's rank
# rather than of the group's size. Inf when a group alone determines a
# coefficient (I - U'U singular): the others cannot predict it.
left_out_ss <- function(X, y, group) {
  fit <- qr(X)
  Q <- qr.Q(fit)[, seq_len(fit$rank), drop = FALSE]
  e <- qr.resid(fit, y)
  sum(vapply(split(seq_along(y), group), function(g) {
    U <- Q[g, , drop = FALSE]
    inner <- tryCatch(solve(diag(ncol(U)) - crossprod(U), crossprod(U, e[g])),
                      error = function(err) NULL)
    if (is.null(inner)) Inf else sum((e[g] + U %*% inner)^2)
  }, numeric(1)))
}
