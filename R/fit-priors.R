#' Priors of the KOH model
#'
#' `koh_priors()` collects the priors of a calibration: one prior per
#' calibration parameter, the hyperpriors of the Gaussian processes and the
#' emulator's mean. The hyperpriors are those of Chong and Menberg (2018):
#' flat priors on the calibration parameters, `rho = exp(-beta / 4) ~
#' Beta(1, 0.3)` for every correlation parameter, and Gamma priors (shape,
#' rate) on the precisions `lambda_eta ~ Gamma(10, 10)`, `lambda_delta ~
#' Gamma(10, 0.3)` and `lambda_e ~ Gamma(10, 0.03)`, which encode the
#' ordering noise < discrepancy < simulator variance on the standardised
#' scale. The emulator has a linear mean by default (Kennedy and O'Hagan
#' 2001), which covered the truth more often than the paper's zero mean in
#' `bench/bench-reliability.R`; `emulator_mean = "zero"` gives the paper's
#' model exactly.
#'
#' Two named sets read the Gamma priors. `set = "paper"` (the default) takes
#' them on the standardised output scale, as the paper does: the emulator's
#' prior variance is about that of the runs, which a zero-mean emulator has
#' to carry. `set = "scaled"` divides that variance by what the emulator
#' mean leaves (`v`, the runs' variance about their least-squares fit on
#' the mean's columns; 0.2-0.25 on the benchmark problems with the linear
#' mean), so the Gaussian process is not asked for variance the mean has
#' already explained. Use "scaled" when a linear mean explains nearly all
#' of the runs (a small `v`) and the fit's
#' `lambda_eta` sits far above its prior; measured on the benchmark
#' (`bench/results/`), it did not make more fits converge at `v` near
#' 0.2, so it is not the default.
#'
#' @param tf A named list of priors for the calibration parameters, each made
#'   by [prior_normal()] or [prior_uniform()], e.g. from [prior_strength()].
#'   Parameters left out get the flat prior `U(0, 1)` on their scaled range.
#' @param set The named prior set the Gamma priors are read in. `"paper"`:
#'   as given, on the standardised output scale (the paper's). `"scaled"`:
#'   the emulator precision's rate is multiplied by `v`, the runs' variance
#'   about the least-squares fit of the emulator mean, so that the
#'   emulator's prior variance is that of what the mean leaves to the
#'   Gaussian process rather than that of the runs (`v` = 1, and the sets
#'   agree, for a zero or constant mean). See Details for when to use which.
#' @param rho_eta,rho_delta Shape parameters `c(a, b)` of the Beta priors on
#'   the emulator's and the discrepancy's correlation parameters.
#' @param lambda_eta,lambda_delta,lambda_e Shape and rate `c(shape, rate)` of
#'   the Gamma priors on the emulator, discrepancy and noise precisions.
#' @param lambda_shift Shape and rate of the Gamma prior on the precision of
#'   the months' shifts in the noise ([calibrate()]'s `noise_shift`), on
#'   the standardised scale: the default `c(1, 0.01)`, an exponential prior
#'   of mean 100 (a shift's sd about 0.1 of the runs' sd), leaves the
#'   training months' shifts to set it.
#' @param gamma_sd Standard deviation of the normal(0, sd) prior on the
#'   coefficients of parametric discrepancy terms (see [extend()]), on the
#'   standardised output scale per range of the covariate (its largest
#'   minus its smallest value): `1` lets a term move the output across the
#'   covariate's range by about one standard deviation of the simulations.
#' @param emulator_mean The mean `h(x, t)' b` of the emulator (Kennedy and
#'   O'Hagan 2001): `"linear"` (a constant plus a linear term in every
#'   observable input and calibration parameter, on their scaled ranges),
#'   `"constant"`, or `"zero"`, the paper's zero-mean emulator.
#' @param mean_sd Standard deviation of the normal(0, sd) prior on each
#'   coefficient `b` of the emulator mean, on the standardised output scale
#'   per unit of the scaled \[0, 1\] inputs: `3` lets the mean span a few
#'   standard deviations of the simulations across an input's range.
#' @param nugget A small jitter that keeps the emulator's covariance
#'   positive definite when inputs or runs nearly coincide. It is added to
#'   each factor of the emulator kernel where rows are equal, the x factor
#'   and the t factor separately, `(k_x + nugget) (k_t + nugget)` on the
#'   diagonal, so that grid designs keep their Kronecker structure (see
#'   [calibrate()], `structure`). Not part of the paper's model; the default
#'   `1e-6` changes no result that matters. Raise it (e.g. to `1e-4`) if a
#'   fit reports a covariance that is not positive definite.
#' @return An object of class `bayesbem_priors`.
#' @family priors
#' @export
#' @examples
#' koh_priors()
#' koh_priors(tf = list(equipment_power_density = prior_normal(21.9, 0.2)))
koh_priors <- function(tf = list(), set = c("paper", "scaled"), rho_eta = c(1, 0.3), rho_delta = c(1, 0.3),
                       lambda_eta = c(10, 10), lambda_delta = c(10, 0.3),
                       lambda_e = c(10, 0.03), lambda_shift = c(1, 0.01), gamma_sd = 1,
                       emulator_mean = c("linear", "constant", "zero"), mean_sd = 3,
                       nugget = 1e-6) {
  if (!is.list(tf) || (length(tf) > 0L && (is.null(names(tf)) || any(names(tf) == ""))) ||
      !all(vapply(tf, inherits, logical(1), "bayesbem_prior"))) {
    abort_bayesbem(c("{.arg tf} must be a named list of priors.",
                     i = "Make each with {.fn prior_normal} or {.fn prior_uniform}, named by its parameter."),
                   "prior")
  }
  hyper <- list(rho_eta = rho_eta, rho_delta = rho_delta, lambda_eta = lambda_eta,
                lambda_delta = lambda_delta, lambda_e = lambda_e, lambda_shift = lambda_shift)
  for (nm in names(hyper)) {
    v <- hyper[[nm]]
    if (!is.numeric(v) || length(v) != 2L || !all(is.finite(v)) || any(v <= 0)) {
      abort_bayesbem(c("{.arg {nm}} must be two positive numbers.",
                       x = "It is {.val {format(v)}}."),
                     "prior")
    }
  }
  set <- match_choice(set)
  check_number(nugget, "prior")
  check_number(gamma_sd, "prior", positive = TRUE)
  emulator_mean <- match_choice(emulator_mean)
  check_number(mean_sd, "prior", positive = TRUE)
  structure(c(list(tf = tf, set = set), hyper,
              list(gamma_sd = gamma_sd, emulator_mean = emulator_mean, mean_sd = mean_sd,
                   nugget = nugget)),
            class = "bayesbem_priors")
}

#' Priors for one calibration parameter
#'
#' `prior_uniform()` is the flat prior `U(0, 1)` on the parameter's scaled
#' range (its design range). `prior_normal(mu, sd)` is a normal prior
#' truncated to the design range, with `mu` in the parameter's physical units
#' (mapped to \[0, 1\] by the package) and `sd` on the \[0, 1\] scale, as in
#' the paper (weakly informative `sd = 0.2`, specific informative
#' `sd = 0.05`).
#'
#' @param mu Prior mean in physical units; must lie in the design range.
#' @param sd Prior standard deviation on the \[0, 1\] scale.
#' @return An object of class `bayesbem_prior`.
#' @family priors
#' @export
#' @examples
#' prior_uniform()
#' prior_normal(mu = 21.9, sd = 0.2)
prior_normal <- function(mu, sd) {
  if (!is.numeric(mu) || length(mu) != 1L || !is.finite(mu)) {
    abort_bayesbem("{.arg mu} must be one finite number.", "prior")
  }
  if (!is.numeric(sd) || length(sd) != 1L || !is.finite(sd) || sd <= 0) {
    abort_bayesbem(c("{.arg sd} must be one positive number.",
                     x = "It is {.val {format(sd)}}.",
                     i = "The paper's strengths are 0.2 (weakly informative) and 0.05 (specific)."),
                   "prior")
  }
  structure(list(family = "normal", mu = mu, sd = sd), class = "bayesbem_prior")
}

#' @rdname prior_normal
#' @export
prior_uniform <- function() {
  structure(list(family = "uniform"), class = "bayesbem_prior")
}

#' @export
format.bayesbem_prior <- function(x, ...) {
  if (x$family == "uniform") "U(0, 1)" else sprintf("N(%s, %s) on [0, 1]", format(x$mu), format(x$sd))
}

#' @export
print.bayesbem_prior <- function(x, ...) {
  rlang::check_dots_empty()
  cat("<bayesbem_prior>", format(x), "\n")
  invisible(x)
}

#' The paper's three prior strengths
#'
#' Builds the calibration-parameter priors of one of the strengths of prior
#' information compared by
#' Chong and Menberg (2018): `"flat"` (`U(0, 1)`), `"weak"` (`N(mu, 0.2)`)
#' or `"specific"` (`N(mu, 0.05)`), all on the \[0, 1\] scale and truncated
#' to it.
#'
#' @param strength One of `"flat"`, `"weak"` or `"specific"`.
#' @param mu A named numeric vector of prior means in physical units, one per
#'   calibration parameter (the modeller's best guess, e.g. the initial
#'   value); not needed for `"flat"`.
#' @return A named list of priors for the `tf` argument of [koh_priors()].
#' @family priors
#' @export
#' @examples
#' prior_strength("weak", mu = c(equipment_power_density = 21.9))
#' koh_priors(tf = prior_strength("specific", mu = c(fan_total_efficiency = 0.5)))
prior_strength <- function(strength = c("flat", "weak", "specific"), mu = NULL) {
  strength <- match_choice(strength)
  if (strength == "flat") {
    return(lapply(stats::setNames(nm = names(mu)), function(i) prior_uniform()))
  }
  if (!is.numeric(mu) || is.null(names(mu)) || any(names(mu) == "")) {
    abort_bayesbem(c("{.arg mu} must be a named numeric vector for the {.val {strength}} prior.",
                     i = "Give each calibration parameter's best guess in physical units, e.g. {.code c(equipment_power_density = 21.9)}."),
                   "prior")
  }
  sd <- c(weak = 0.2, specific = 0.05)[[strength]]
  lapply(mu, prior_normal, sd = sd)
}

#' @export
print.bayesbem_priors <- function(x, ...) {
  rlang::check_dots_empty()
  tf <- if (length(x$tf) == 0L) "U(0, 1) for every parameter" else
    paste(paste(names(x$tf), vapply(x$tf, format, character(1)), sep = ": ", collapse = "; "),
          "(others U(0, 1))")
  cat_lines("{.cls bayesbem_priors}",
            "* tf: {tf}",
            "* rho_eta ~ Beta({x$rho_eta[1]}, {x$rho_eta[2]}), rho_delta ~ Beta({x$rho_delta[1]}, {x$rho_delta[2]})",
            "* lambda_eta ~ Gamma({x$lambda_eta[1]}, {x$lambda_eta[2]}{if (prior_set_of(x) == \"scaled\") \" v\" else \"\"}), lambda_delta ~ Gamma({x$lambda_delta[1]}, {x$lambda_delta[2]}), lambda_e ~ Gamma({x$lambda_e[1]}, {x$lambda_e[2]})",
            "* lambda_shift ~ Gamma({shift_prior(x)[1]}, {shift_prior(x)[2]}) (with a shift per month)",
            "* emulator mean: {emulator_mean_label(x)}",
            if (prior_set_of(x) == "scaled") "* v: the runs' variance about the least-squares emulator mean")
  invisible(x)
}

# The prior of the months' shifts' precision (priors made before it
# existed: the default).
shift_prior <- function(priors) {
  priors$lambda_shift %||% eval(formals(koh_priors)$lambda_shift)
}

# The emulator mean of a set of priors, in words (fits made before it
# existed have the paper's zero mean).
emulator_mean_label <- function(priors) {
  switch(emulator_mean_of(priors),
         zero = "zero (the paper's)",
         constant = sprintf("constant, b ~ N(0, %s)", priors$mean_sd),
         linear = sprintf("linear in x and t, b ~ N(0, %s)", priors$mean_sd))
}

emulator_mean_of <- function(priors) priors$emulator_mean %||% "zero"

prior_set_of <- function(priors) priors$set %||% "paper"

check_priors <- function(priors, call = rlang::caller_env()) {
  if (!inherits(priors, "bayesbem_priors")) {
    abort_bayesbem(c("{.arg priors} must be made by {.fn koh_priors}.",
                     x = "It is {.obj_type_friendly {priors}}."),
                   "prior", call = call)
  }
}

# Which columns of [1, x, t] the emulator mean uses: a (1 + p + q) x n_b
# selection matrix (koh_prior_data.stan's b_select).
mean_selection <- function(priors, p, q) {
  all <- diag(1 + p + q)
  switch(emulator_mean_of(priors), zero = all[, 0, drop = FALSE],
         constant = all[, 1, drop = FALSE], linear = all)
}
