#' Calibrate the shipped case study with the paper's settings
#'
#' Runs the calibration of Chong and Menberg (2018) on [seb_field] and
#' [seb_sim]: three calibration parameters (fan total efficiency, equipment
#' power density, infiltration), the paper's hyperpriors, flat priors on the
#' parameters, the package's linear emulator mean (`priors =
#' koh_priors(emulator_mean = "zero")` gives the paper's zero mean), the
#' paper's joint model (every hyperparameter sampled: `modular = FALSE`,
#' where [calibrate()] fits in two stages by default), and NUTS with 4
#' chains, half of each warm-up. Prints the
#' posterior summary, the convergence diagnostics and the ASHRAE Guideline 14
#' metrics, and draws the posteriors, the paper's Fig 6 comparison and the
#' trace plots.
#'
#' The paper ran 500 iterations per chain; here they leave two emulator
#' length scales (`beta_eta[temp]`, `beta_eta[rh]`, whose posterior is
#' bimodal) unconverged, so the default is 2000, which converges (every
#' R-hat below 1.01, at [calibrate()]'s default `adapt_delta = 0.99`) in
#' under a minute on one core. `iter = 500` gives the paper's run, with a
#' convergence warning.
#'
#' @param chains,iter,seed,cores Passed to [calibrate()].
#' @param priors A [koh_priors()] object.
#' @param plot_dir A directory to save the plots in as PNG files
#'   (`posteriors.png`, `components.png`, `trace.png`); by default they are
#'   drawn on the current graphics device.
#' @return The `bayesbem_fit`, invisibly.
#' @family case study
#' @export
#' @examples
#' \donttest{
#' fit <- run_case_study(chains = 1, iter = 300, plot_dir = tempdir())
#' }
run_case_study <- function(chains = 4L, iter = 2000L, seed = 2018L,
                           cores = min(chains, parallel::detectCores(logical = FALSE), na.rm = TRUE),
                           priors = koh_priors(), plot_dir = NULL) {
  fit <- calibrate(koh_data(bayesbem::seb_field, bayesbem::seb_sim), priors = priors,
                   chains = chains, iter = iter, seed = seed, cores = cores, modular = FALSE)
  print(fit)
  cat("\n")
  print(check_convergence(fit, warn = FALSE))
  cat("\nASHRAE Guideline 14 metrics of the calibrated predictions (percent):\n")
  print(calibration_metrics(fit))
  plots <- list(posteriors = plot_posteriors(fit), components = plot_components(fit),
                trace = plot_trace(fit))
  if (is.null(plot_dir)) {
    lapply(plots, print)
  } else {
    dir.create(plot_dir, showWarnings = FALSE, recursive = TRUE)
    for (name in names(plots)) {
      path <- file.path(plot_dir, paste0(name, ".png"))
      ggplot2::ggsave(path, plots[[name]], width = 10, height = if (name == "posteriors") 4 else 7,
                      dpi = 120)
    }
    cli::cli_inform("Plots saved in {.path {plot_dir}}.")
  }
  invisible(fit)
}
