#' Study the effect of the calibration parameters' priors
#'
#' The prior study of Chong and Menberg (2018): the same calibration with
#' the paper's three prior strengths on the calibration parameters, `"flat"`
#' (`U(0, 1)`), `"weak"` (`N(mu, 0.2)`) and `"specific"` (`N(mu, 0.05)`), on
#' the parameters' design ranges mapped to \[0, 1\] (see [prior_strength()]).
#' It reports how the posteriors move and narrow (the paper's Fig 5) and the
#' calibrated predictions' CVRMSE and NMBE on the training data and, when
#' given, held-out data (the paper's Table 3).
#'
#' Fits run through [future.apply::future_lapply()]: sequentially by
#' default, in parallel with e.g. `future::plan(future::multisession,
#' workers = 3)` (then give each fit `cores = 1`). Progress is reported
#' through progressr: wrap the call in [progressr::with_progress()].
#'
#' @param field A [koh_data()] object, or the field data frame (then `sim`
#'   is required).
#' @param sim The simulation data frame when `field` is a data frame.
#' @param strengths Prior strengths to compare: any of `"flat"`, `"weak"` and
#'   `"specific"`.
#' @param mu A named numeric vector of prior means in physical units, one
#'   per calibration parameter (the modeller's best guess, e.g. the
#'   simulator's initial values); needed for the `"weak"` and `"specific"`
#'   strengths.
#' @param newdata,obs Optional held-out data: a data frame with the
#'   observable inputs, and the measured output of each of its rows.
#' @param priors A [koh_priors()] object giving the GP hyperpriors; its
#'   calibration-parameter priors are replaced by each strength's.
#' @param seed Random seed of every fit (the same for all strengths).
#' @template args-ndraws
#' @param ... Further arguments to [calibrate()], e.g. `chains`, `iter`,
#'   `cores`.
#' @return An object of class `bayesbem_prior_study`: a list with `fits` (the
#'   `bayesbem_fit` of each strength), `strengths`, `posteriors` (one row per strength
#'   and parameter: `mean`, `sd`, quantiles `q5` to `q95` in physical units
#'   and `scaled`, the median on \[0, 1\]), `metrics` (one row per strength
#'   and data set: `n`, `cvrmse`, `nmbe`, `calibrated`) and `densities` (the
#'   posterior densities that [plot_prior_study()] draws). Printing and
#'   plotting do not need `fits`: set it to `NULL` to store a small study.
#' @family studies
#' @export
#' @examples
#' \donttest{
#' mu <- c(fan_total_efficiency = 0.6, equipment_power_density = 21.9,
#'         infiltration_per_exterior_area = 0.0011)
#' study <- study_priors(seb_field, seb_sim, strengths = c("flat", "specific"), mu = mu,
#'                       chains = 1, iter = 300, seed = 1, refresh = 0)
#' study
#' plot(study)
#' }
study_priors <- function(field, sim = NULL, strengths = c("flat", "weak", "specific"), mu = NULL,
                         newdata = NULL, obs = NULL, priors = koh_priors(), seed = 2018L,
                         ndraws = NULL, ...) {
  data <- as_koh_data(field, sim)
  known <- c("flat", "weak", "specific")
  if (!is.character(strengths) || length(strengths) == 0L || !all(strengths %in% known) ||
      anyDuplicated(strengths)) {
    abort_bayesbem(c("{.arg strengths} must be distinct prior strengths among {.val {known}}.",
                     x = "It is {.val {format(strengths)}}."),
                   "argument")
  }
  check_priors(priors)
  check_held_out(newdata, obs, data)
  call <- rlang::current_env()
  jobs <- lapply(stats::setNames(nm = strengths), function(strength) {
    strength_priors <- priors
    strength_priors$tf <- prior_strength(strength, mu)
    # checks the means against the design ranges before any fit starts
    koh_stan_data(data, strength_priors, call = call)
    list(field = data, priors = strength_priors, seed = seed, ...)
  })
  fits <- run_fits(jobs)
  structure(list(fits = fits, strengths = strengths, posteriors = study_posteriors(fits, "strength"),
                 metrics = study_metrics(fits, "strength", newdata, obs, ndraws),
                 densities = prior_study_densities(fits)),
            class = "bayesbem_prior_study")
}

# Each strength's posterior densities (see plot_posteriors_data()).
prior_study_densities <- function(fits) {
  rows <- lapply(names(fits), function(strength) {
    d <- plot_posteriors_data(fits[[strength]])
    d <- d[d$curve == "posterior", c("parameter", "value", "density")]
    data.frame(strength = strength, d, row.names = NULL)
  })
  out <- do.call(rbind, rows)
  out$strength <- factor(out$strength, levels = names(fits))
  out
}

#' @export
print.bayesbem_prior_study <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  print_study(x, "strength",
              "{.cls bayesbem_prior_study}: {length(x$strengths)} prior strength{?s} ({.val {x$strengths}})", digits)
}
