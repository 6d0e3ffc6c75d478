#' Calibrate the shipped case study with the paper's settings
#'
#' Runs the calibration of Chong and Menberg (2018) on [seb_field] and
#' [seb_sim]: three calibration parameters (fan total efficiency, equipment
#' power density, infiltration), the paper's hyperpriors, flat priors on the
#' parameters, and NUTS with 4 chains of 500 iterations, half of them
#' warm-up. Prints the summary.
#'
#' @param chains,iter,seed,cores Passed to [calibrate()].
#' @param priors A [koh_priors()] object.
#' @return The `koh_fit`, invisibly.
#' @family case study
#' @export
#' @examples
#' \donttest{
#' fit <- run_case_study(chains = 1, iter = 300)
#' }
run_case_study <- function(chains = 4L, iter = 500L, seed = 2018L,
                           cores = min(chains, parallel::detectCores(logical = FALSE), na.rm = TRUE),
                           priors = koh_priors()) {
  fit <- calibrate(koh_data(bayesbem::seb_field, bayesbem::seb_sim), priors = priors,
                   chains = chains, iter = iter, seed = seed, cores = cores)
  print(fit)
  invisible(fit)
}
