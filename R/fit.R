#' Calibrate a simulator against field data (KOH model)
#'
#' Fits the Kennedy-O'Hagan model of Chong and Menberg (2018) with Stan's
#' NUTS sampler: a Gaussian-process emulator of the simulator over
#' `(x, t)`, a Gaussian-process discrepancy over `x`, and observation noise,
#' with the priors of [koh_priors()]. The Stan program is compiled when the
#' package is installed.
#'
#' @param field A [koh_data()] object, or the field data frame (then `sim` is
#'   required and columns are found as [koh_data()] describes, each
#'   calibration parameter on the scale `scales = "auto"` picks; pass
#'   `koh_data(field, sim, scales = "identity")` for the paper's model).
#' @param sim The simulation data frame when `field` is a data frame.
#' @param priors A [koh_priors()] object.
#' @param chains,iter Number of Markov chains and iterations per chain
#'   (including warm-up). By default 4000 iterations; for a modular fit of
#'   more than 36 field rows 2000 with the separable emulator and 3000 with
#'   the basis emulator and the product discrepancy; 2000 with the additive
#'   discrepancy (see `discrepancy_kernel` and `control`).
#' @param warmup Warm-up iterations per chain; defaults to half of `iter`,
#'   except in the defaults of a basis fit: 1000 of its 3000 iterations
#'   with the product discrepancy, 500 of 2000 with the additive one.
#' @param seed Random seed; by default one is drawn and stored in the result
#'   so the fit can be repeated.
#' @param cores Number of chains run at once, each in its own process. By
#'   default `getOption("mc.cores")`, else every core of the machine (two
#'   under `R CMD check`'s core limit); never more than `chains`.
#' @param control Sampler control for [rstan::sampling()], a list whose
#'   entries replace the defaults one by one (`list(max_treedepth = 12)`
#'   keeps the default `adapt_delta`). The defaults: up to 36 field rows
#'   `adapt_delta = 0.99`; above, 0.95 with a dense metric (`metric =
#'   "dense_e"`) for the basis emulator and 0.9 for the separable one
#'   (Stan's own is 0.8). Smaller steps are what the curved posteriors of
#'   the emulator's length scales and the fan / equipment ridge of building
#'   models need to avoid divergent transitions and to mix; the dense
#'   metric fits the straight ridge the basis fit samples (see `emulator`).
#'   The additive discrepancy's chains start at a mode, so they also take
#'   `max_treedepth = 8` and a first metric after 25 warm-up iterations
#'   (`adapt_init_buffer = 25`). Each default is the one that converged most often in the reliability
#'   benchmark (`bench/results/reliability.md`).
#' @param predict_at Optional data frame of observable inputs at which the
#'   calibrated output is sampled inside Stan as extra parameters (the
#'   paper's Appendix D; about twice as slow). Read them with
#'   `predict(fit, method = "sampled")`. [predict.bayesbem_fit()] gives the same
#'   predictions by exact conditioning after the fit, for any inputs.
#' @param structure Which likelihood the Stan program computes: `"grid"`
#'   when every simulation run was made at every field
#'   input, as in the paper's workflow: the emulator covariance is then a
#'   Kronecker product and each gradient costs O(mt^3 + n^3) for mt runs and
#'   n field rows; `"dense"` for any design, O((n + m)^3).
#'   Both give the same posterior. `"auto"` (the default) uses the grid
#'   likelihood whenever the data allow it (see `koh_data()$grid`) and
#'   `predict_at` is not given.
#' @param covariates Optional data frame, one row per field row, whose
#'   columns enter the discrepancy as parametric terms (see [extend()], which
#'   is the usual way to add them).
#' @param modular Fit in two stages (Liu, Bayarri and Berger 2009): the
#'   emulator's hyperparameters from the simulation runs alone (on at most 60
#'   of the grid inputs), at the mode of their posterior, then the
#'   calibration parameters, the discrepancy and the noise sampled with the
#'   emulator fixed there (the plug-in emulator of Bayarri et al. 2007).
#'   The mode is the best of 16 quasi-Newton searches from random starts on
#'   Stan's unconstrained scale (`fit$emulator` holds it, with the log
#'   density each search reached; `summary()` says how many reached it).
#'   The field data then cannot pull the emulator into modes that only
#'   explain them, the length scales' modes of equal mass that few runs
#'   leave (and that chains seldom cross) do not split the chains, and each
#'   stage-2 gradient costs one Cholesky factor and one inverse of an
#'   n x n matrix. The price: the emulator's hyperparameters are not
#'   integrated over (its uncertainty given them still is). Needs a grid
#'   design. `"auto"` (the default) fits in two stages on a grid design
#'   (and `predict_at` not given), jointly otherwise: in the reliability
#'   benchmark the two-stage fit converged far more often, covered the
#'   truth about as often and took a fraction of the time
#'   (`bench/results/reliability.md`).
#' @param emulator The emulator stage 2 of a modular fit calibrates with:
#'   `"separable"`, the Gaussian process of the paper, whose correlation is
#'   a product of one over the observable inputs and one over the
#'   parameters; or `"basis"`, a principal-component emulator (Higdon et al.
#'   2008): the runs' outputs at the field rows are decomposed into the
#'   fewest components that hold 99.9 % of their variance around the runs'
#'   mean, the rest taken as white error, and each component's weight is a
#'   Gaussian process over the parameters with its own length scales,
#'   variance and nugget (maximum marginal likelihood; `fit$emulator$basis`).
#'   Both give the emulator's uncertainty at the calibration parameters to
#'   stage 2; the separable one gives it the outputs' shape across the
#'   periods, which at a year of daily data understates the error that
#'   moves the calibration (`bench/results/`). Predictions,
#'   leave-one-out and the discrepancy tools use the separable emulator
#'   fitted at stage 1 in either case; [validate_emulator()] and
#'   [identifiability()] read the one stage 2 used. A basis fit's stage 2
#'   samples the calibration parameters on \[0, 1\] as `tf_u`,
#'   `tf = g(tf_u)` with `g` within 0.02 of the identity on
#'   \[0.05, 0.95\] and exponential tails beyond (instead of Stan's logit,
#'   on which the ridge bends towards the range's ends). Needs a modular
#'   fit.
#'   `"auto"` (the default) chooses `"basis"` for a modular fit of more
#'   than 36 field rows, `"separable"` otherwise.
#' @param discrepancy_kernel The discrepancy's Gaussian process:
#'   `"product"`, the paper's, one squared-exponential kernel over all
#'   observable inputs jointly, whose likelihood factors an n x n matrix
#'   per gradient; or `"additive"`, a sum of one Gaussian process per
#'   input, each with its own length scale (at most that of `rho_delta =
#'   0.98`, 2.5 input ranges: longer ones are flat over the data anyway)
#'   and variance `1 / (p lambda_delta)`, in the Hilbert-space
#'   approximation of Riutort-Mayol et al. (2023): 40 basis functions per
#'   input, within 0.025 of the kernel's variance, so that a gradient's
#'   cost does not grow with the rows (`bench/results/gradient.md`). Needs the
#'   basis emulator and periods of one length. `"auto"`
#'   (the default) is, where both apply, the one whose fit is predicted to
#'   cost less: `"additive"` from about 160 rows of three inputs (a year of
#'   days, of hours), `"product"` below and wherever the additive one does
#'   not apply (monthly bills, periods of different lengths). Where both
#'   run, their posteriors and held-out intervals agree
#'   (`bench/results/discrepancy-kernel.md`). A sum
#'   cannot hold an effect of two inputs together (a load of weekend
#'   hours alone), which then biases the parameters: give such a
#'   combination as an input of its own, as the hourly simulators'
#'   `daytype_hour` (see [bem_simulator()]).
#' @param noise_correlation The observation noise's correlation between
#'   consecutive periods: `"none"`, independent noise (the paper's); or
#'   `"ar1"`, an AR(1) process over periods one step apart (hourly
#'   residuals persist for hours), with its coefficient `phi` sampled
#'   (flat prior on (-1, 1)); the emulator's truncated components share
#'   it. A gap in the times or a step back starts a new run of
#'   consecutive periods. Needs `discrepancy_kernel = "additive"`, whose
#'   likelihood it keeps at the same cost, and the field rows' times (the
#'   data's `period` column, e.g. [field_hours()]'s `time`). Predictions
#'   with noise, scenarios and savings then draw AR(1) noise over their
#'   periods, so that a total over many hours carries the correlation.
#'   `"auto"` (the default) is `"ar1"` where it applies, the additive
#'   discrepancy over rows with times of which some follow one another
#'   (meter data by the hour or day; AR(1) holds white noise at `phi = 0`),
#'   and `"none"` elsewhere (bills: the paper's).
#' @param noise_shift A shift per calendar month in the observation noise:
#'   `"month"` adds to each row's noise its month's shift, `N(0, 1 /
#'   lambda_shift)` independent between months (prior
#'   [koh_priors()]`$lambda_shift`), so that a month's total carries the
#'   month-to-month movement of a meter's use that the inputs do not
#'   explain (term time, a tenant's change); `"none"` leaves it out.
#'   Needs `discrepancy_kernel = "additive"` (its likelihood takes the
#'   months as further basis columns, at no cost in the rows) and the
#'   field rows' times. Predictions with noise then draw each training
#'   month's shift given the data and each other month's from its prior,
#'   shared by the month's periods: a held-out month's total is as
#'   uncertain as the training months' shifts say. `"auto"` (the default)
#'   is `"month"` for the additive discrepancy over rows with times, at
#'   least three months of them and several rows a month (meter data by
#'   the hour or day), `"none"` elsewhere
#'   (`inst/notes/decisions/S12-a-shift-per-month.md`).
#' @param minor_modes What to do with chains stuck in a minor mode of the
#'   posterior: `"drop"` (the default) deals with them as below, with a
#'   message; `"keep"` keeps every chain as it ran. Each chain's mode gets a
#'   Laplace estimate of its posterior mass from the chain's own draws (mean
#'   log density plus half the log determinant of their covariance on Stan's
#'   unconstrained scale). Chains whose mode holds less than e^-5 of the
#'   best chain's mass are dropped when two chains remain; when the best
#'   chain alone found the main mode they are run again from its draws
#'   (provided it had no divergent transition), so the fit keeps all its
#'   chains (in a modular fit, its stage-2 chains). Chains in modes of
#'   similar mass are always kept, and [check_convergence()] reports that
#'   they disagree. `fit$settings$dropped` and `fit$settings$restarted` list
#'   the chains. In stage 2 of a modular fit, a
#'   minor mode that puts a calibration parameter outside the main mode's
#'   90 % interval is kept instead (`fit$settings$kept_moved`), with a
#'   message naming the parameters: with the emulator fixed, such modes can
#'   be the emulator's error rather than the data's, and the emulator can
#'   check out at the main mode while being wrong between the modes (the
#'   truth can lie between them). The fit
#'   then fails [check_convergence()], whose hint says to check the
#'   emulator over both modes with [validate_emulator()] and add runs there
#'   with [design_posterior()]. A joint fit drops such chains and its
#'   message says to refit with `"keep"` and check the emulator.
#' @param progress Show a progress bar over all chains while sampling
#'   (Stan's own per-chain iteration lines are not printed). The default is
#'   the option `bayesbem.progress`, `TRUE` unless set.
#' @param ... Further arguments to [rstan::sampling()]: `init`, `init_r`,
#'   `refresh`, `thin`, `save_warmup`, `sample_file`, `diagnostic_file`,
#'   `verbose`, `check_data`, `show_messages` or `enable_random_init` (any
#'   other is an error). Starting values given as a list per chain name
#'   the Stan program's parameters, `tf` for the calibration parameters on
#'   \[0, 1\]; a basis fit samples them as `tf_u` (on a scale linear inside
#'   \[0, 1\]) and converts the `tf` given.
#' @section Several outputs: On data of several outputs (meters: long
#'   tables with an `output` column, see [koh_data()]) the fit is modular,
#'   on each output's grid: stage 1 fits each output's emulator to its
#'   runs, and stage 2 samples the calibration parameters the outputs share
#'   with a discrepancy and a noise for each output. Given the parameters
#'   the outputs are independent, so the log density is the sum of the
#'   outputs' and a gradient costs the sum of theirs. The fit prints the
#'   shared parameters and each output's discrepancy and noise;
#'   [output_fit()] gives each output's view, a fit of one output whose
#'   draws are the shared ones and the output's own, which every tool
#'   takes; [predict()], [predict_scenario()] and [savings()] give every
#'   output and their totals. `covariates` is then a list of tables named by
#'   output, and starting values give `lambda_delta` and `lambda_e` one
#'   element per output.
#' @section Linear algebra: With many field rows (daily data) each gradient
#'   of a grid or modular fit is one Cholesky factor and one inverse of the
#'   n x n covariance of the field outputs. They are computed by Eigen, or
#'   by R's LAPACK when R is linked to an optimised BLAS (OpenBLAS, MKL,
#'   BLIS, ATLAS or Apple's Accelerate, told by the name of
#'   `extSoftVersion()[["BLAS"]]`), which is faster at large n
#'   (`bench/results/gradient.md`). To speed up such fits, link R to
#'   OpenBLAS, its serial build since the chains already share the cores
#'   (on Debian or Ubuntu, `apt install libopenblas0-serial`).
#'
#'   The cost grows with the cube of the rows and the memory with their
#'   square: a fit whose matrices would not fit in the memory available
#'   (the chains that run at once each hold theirs), or that would sample
#'   for more than `getOption("bayesbem.max_hours", 24)` hours per chain at
#'   the measured cost per gradient, is refused before anything runs
#'   (class `bayesbem_error_too_large`), saying what it would need: a year
#'   of hourly data is, a year of daily data is not.
#'   A fit of more than 120 field rows on Eigen says so, once per session.
#'   `options(bayesbem.lapack = TRUE)` or `FALSE` overrides the choice, and
#'   `fit$settings$lapack` records it: the two give the same log density to
#'   rounding, but a seeded fit repeats exactly only with the same choice.
#' @section Before the fit: On a grid design (every run at every field
#'   row) the measured total of each output must lie within the runs'
#'   totals over the same rows; otherwise no setting the runs span reaches
#'   the meter (a building of the wrong size, or the wrong units), the fit
#'   would leave the whole gap to the discrepancy, and `calibrate()` stops
#'   with an error of class `bayesbem_error_prior_misses` before it
#'   samples.
#' @section Range limits: A calibration parameter whose posterior piles
#'   against a limit of its range (more than 10 % of the draws within 2 % of
#'   the range from it, five times what a flat posterior holds there) is a
#'   warning of class `bayesbem_warning_range_limit` naming the parameter,
#'   the limit and what to do: the data ask for a value the range excludes,
#'   or for a cause the model lacks.
#' @return An object of class `bayesbem_fit` (on several outputs also
#'   `bayesbem_fit_outputs`, whose methods of the package's verbs apply
#'   each to every output, see [output_fit()]): the posterior draws of the Stan program's parameters (`draws`, a
#'   [posterior::draws_array] on the program's scale; each output's own
#'   variables named `"<output>:<variable>"` on several outputs), the
#'   sampler's diagnostics, the [koh_data()] (with its scaling), the priors
#'   and the sampler settings. Use `print()`, `summary()` and
#'   [posterior::as_draws()] (physical units) on it.
#' @family calibration
#' @export
#' @examples
#' \donttest{
#' fit <- calibrate(seb_field, seb_sim, chains = 1, iter = 300, seed = 1)
#' fit
#' }
calibrate <- function(field, sim = NULL, priors = koh_priors(), chains = 4L,
                      iter = NULL, warmup = NULL, seed = NULL,
                      cores = getOption("mc.cores", default_cores()),
                      control = NULL, predict_at = NULL,
                      structure = c("auto", "grid", "dense"), covariates = NULL,
                      modular = "auto", emulator = c("auto", "separable", "basis"),
                      discrepancy_kernel = c("auto", "product", "additive"),
                      noise_correlation = c("auto", "none", "ar1"),
                      noise_shift = c("auto", "none", "month"), minor_modes = c("drop", "keep"),
                      progress = getOption("bayesbem.progress", TRUE), ...) {
  spec <- calibration_spec(field, sim, priors = priors, chains = chains, iter = iter,
                           warmup = warmup, cores = cores, control = control,
                           predict_at = predict_at, structure = structure,
                           covariates = covariates, modular = modular, emulator = emulator,
                           discrepancy_kernel = discrepancy_kernel,
                           noise_correlation = noise_correlation, noise_shift = noise_shift,
                           minor_modes = minor_modes, dots = list(...))
  seed <- seed %||% sample.int(.Machine$integer.max, 1L)
  check_count(seed)
  check_bool(progress)
  data <- spec$data
  fit_env <- environment()
  sampler <- list(chains = chains, iter = spec$iter, warmup = spec$warmup, seed = seed,
                  cores = min(cores, chains), control = spec$control, args = list(...),
                  progress = progress, minor_modes = spec$minor_modes,
                  on_failure = function(messages) {
                    abort_sampling_failure(output_data(data)[[1]], priors$nugget, spec$structure,
                                           messages, call = fit_env)
                  })
  # the emulator named by the spec; stage 1 is the fitted emulator (of each output)
  stage1 <- if (spec$modular) fit_stage1(data, priors, seed, sampler$on_failure, spec$emulator)
  sampler$args$init <- stan_inits(sampler$args$init, spec$emulator)
  sampler$start_at_mode <- spec$discrepancy_kernel == "additive"
  hsgp <- if (spec$discrepancy_kernel == "additive") hsgp_design()
  program <- stan_program(data, priors, stage1, spec$emulator, spec$modular, spec$structure,
                          predict_at, hsgp, spec$segments, spec$shifts)
  label <- sprintf("%s %d chain%s", if (spec$modular) "Stage 2: sampling" else "Sampling",
                   chains, if (chains > 1L) "s" else "")
  stanfit <- do.call(sample_chains, c(list(program$model, program$data, label = label,
                                           keep_moved = spec$modular), sampler))
  settings <- list(chains = chains, iter = spec$iter, warmup = spec$warmup, seed = seed,
                   control = spec$control, structure = spec$structure, modular = spec$modular,
                   emulator = spec$emulator, discrepancy_kernel = spec$discrepancy_kernel,
                   hsgp = hsgp, noise_correlation = spec$noise_correlation,
                   segments = spec$segments, noise_shift = spec$noise_shift, shifts = spec$shifts,
                   minor_modes = spec$minor_modes, lapack = spec$lapack,
                   dropped = attr(stanfit, "dropped"), restarted = restarted_chains(stanfit),
                   kept_moved = attr(stanfit, "kept_moved"))
  fit <- stanfit_fit(stanfit, data, priors, settings, emulator = stage1,
                     predict_at = if (!is.null(predict_at)) predict_at[data$names$x])
  if (spec$several) fit <- with_output_views(fit)
  inform_minor_modes(fit$settings$dropped, fit$settings$restarted,
                     moved_parameters(output_fit_list(fit)[[1]], attr(stanfit, "minor_tf")),
                     fit$settings$kept_moved)
  check_convergence(fit)
  warn_range_limits(fit)
  fit
}

# Every choice of a fit resolved from the data and calibrate()'s arguments,
# and every check that needs no sampling (sampler arguments, the size, the
# prior's reach): what calibrate() samples with, and what
# calibrate_portfolio() checks before sending a building to a worker.
calibration_spec <- function(field, sim, priors, chains, iter, warmup, cores, control,
                             predict_at, structure, covariates, modular, emulator,
                             discrepancy_kernel, noise_correlation, noise_shift,
                             minor_modes, dots, call = rlang::caller_env()) {
  # the checks' errors name the caller's verb, not this helper
  rlang::local_error_call(call)
  data <- as_koh_data(field, sim)
  several <- inherits(data, "bayesbem_outputs")
  data <- if (several) add_output_terms(data, covariates) else add_discrepancy_terms(data, covariates)
  if (!is.null(covariates) && !is.null(predict_at)) {
    abort_bayesbem(c("{.arg predict_at} cannot be combined with {.arg covariates}.",
                     i = "Predict after the fit with {.fn predict}, giving the covariates in {.arg newdata}."),
                   "argument", call = call)
  }
  check_control_misplaced(dots)
  check_dots_in(dots, sampling_arguments(), "rstan::sampling()")
  check_priors(priors)
  asked <- match_choice(structure, c("auto", "grid", "dense"), "structure", call = call)
  if (several) {
    check_outputs_path(asked, modular, predict_at)
    structure <- "grid"
    modular <- TRUE
  } else {
    structure <- choose_structure(data, asked, predict_at)
    inform_dense(data, structure, asked)
    modular <- choose_modular(modular, data, structure)
  }
  emulator <- choose_emulator(match_choice(emulator, c("auto", "separable", "basis"), "emulator",
                                           call = call), modular, data)
  discrepancy_kernel <- choose_discrepancy_kernel(
    match_choice(discrepancy_kernel, c("auto", "product", "additive"), "discrepancy_kernel",
                 call = call), emulator, data)
  noise_correlation <- choose_noise_correlation(
    match_choice(noise_correlation, c("auto", "none", "ar1"), "noise_correlation", call = call),
    discrepancy_kernel, data)
  # the AR(1) noise's segments of each output's rows, found once
  segments <- if (noise_correlation == "ar1") output_segments(data, call = call)
  noise_shift <- choose_noise_shift(
    match_choice(noise_shift, c("auto", "none", "month"), "noise_shift", call = call),
    discrepancy_kernel, data)
  # each output's rows' months, found once
  shifts <- if (noise_shift == "month") lapply(output_data(data), field_months, call = call)
  defaults <- default_sampling(modular, largest_output(data), emulator, discrepancy_kernel)
  check_count(chains)
  check_count(cores)
  lengths <- sampling_lengths(iter, warmup, defaults)
  lapack <- use_lapack()
  inform_blas(largest_output(data), lapack, modular || is_grid(structure))
  check_fit_size(fit_size(data, structure, modular, lengths$iter, discrepancy_kernel),
                 min(cores, chains))
  check_prior_covers(data)
  list(data = data, several = several, structure = structure, modular = modular,
       emulator = emulator, discrepancy_kernel = discrepancy_kernel,
       noise_correlation = noise_correlation, segments = segments, noise_shift = noise_shift,
       shifts = shifts, iter = lengths$iter,
       warmup = lengths$warmup,
       control = merge_control(control, defaults$control), lapack = lapack,
       minor_modes = match_choice(minor_modes, c("drop", "keep"), "minor_modes", call = call))
}

# The Stan program of a fit and its data (R/fit-stan-data.R), one row per
# kind of fit:
#   joint, dense likelihood      koh.stan, "dense"     koh_stan_data()
#   joint, grid likelihood       koh.stan, "grid"      koh_stan_data()
#   modular, separable emulator  koh.stan, "modular"   modular_stan_data()
#   modular, basis emulator      koh_basis.stan        basis_stan_data()
#     (additive discrepancy, an hsgp_design() `hsgp`: its hsgp block)
# Stage 1 of a modular fit is koh.stan, "emulator" (emulator_stan_data()).
stan_program <- function(data, priors, stage1, emulator, modular, structure, predict_at,
                         hsgp = NULL, segments = NULL, shifts = NULL) {
  if (emulator == "basis") {
    return(list(model = stanmodels$koh_basis,
                data = basis_stan_data(data, priors, stage1, hsgp, segments, shifts)))
  }
  if (modular) {
    return(list(model = stanmodels$koh, data = modular_stan_data(data, priors, stage1)))
  }
  x_pred <- if (!is.null(predict_at)) scale_newdata(data, predict_at, "predict_at")
  list(model = stanmodels$koh, data = koh_stan_data(data, priors, x_pred, structure))
}

# The iterations and warm-up of a fit: the caller's, else the defaults of
# default_sampling(); an `iter` of the caller's own has half of it as warm-up.
sampling_lengths <- function(iter, warmup, defaults, call = rlang::caller_env()) {
  if (!is.null(iter)) check_count(iter, call = call)
  warmup <- warmup %||% if (is.null(iter)) defaults$warmup else floor(iter / 2)
  iter <- iter %||% defaults$iter
  if (!isTRUE(checkmate::check_count(warmup)) || warmup >= iter) {
    abort_bayesbem("{.arg warmup} must be a whole number from 0 to {.arg iter} - 1 ({iter - 1}), not {describe_value(warmup)}.",
                   "argument", call = call)
  }
  list(iter = iter, warmup = warmup)
}

# Stage 1 of a modular fit: the emulator fitted to the runs of each output
# (a list by output when there are several), with its basis emulator when
# stage 2 calibrates with that.
fit_stage1 <- function(data, priors, seed, on_failure, emulator) {
  one <- function(d) {
    stage1 <- fit_emulator(d, priors, seed, on_failure)
    if (emulator == "basis") stage1$basis <- basis_emulator(d)
    stage1
  }
  if (inherits(data, "bayesbem_outputs")) lapply(data$outputs, one) else one(data)
}

# The iterations and sampler control of a fit whose caller gives none: for
# each size and emulator, what converged most often in the reliability
# benchmark (bench/results/reliability.md; why in
# inst/notes/decisions/G2-runs-where-the-posterior-lies.md and
# F5-a-linear-scale-for-tf-in.md). The additive discrepancy's chains
# start at a mode (mode_start()) and sample through the Laplace
# approximation at one (laplace_map()), so a warm-up of 500 iterations, a
# first metric after 50 (not 100) and trees of at most 2^8 steps
# (bench/results/year-hours.md); 1500 draws a chain, as a year of days mixes
# more slowly than a year of hours (bench/results/reliability.md).
default_sampling <- function(modular, n, emulator = "separable", kernel = "product") {
  if (kernel == "additive") {
    return(list(iter = 2000L, warmup = 500L,
                control = list(adapt_delta = 0.95, metric = "dense_e", max_treedepth = 8L,
                               adapt_init_buffer = 25L)))
  }
  if (modular && n > 36L && emulator == "basis") {
    return(list(iter = 3000L, warmup = 1000L,
                control = list(adapt_delta = 0.95, metric = "dense_e")))
  }
  if (modular && n > 36L) {
    return(list(iter = 2000L, warmup = 1000L, control = list(adapt_delta = 0.9)))
  }
  list(iter = 4000L, warmup = 2000L, control = list(adapt_delta = 0.99))
}

# modular = "auto": two stages on a grid design, the joint fit otherwise
# (see the @param). TRUE needs a grid.
choose_modular <- function(modular, data, structure, call = rlang::caller_env()) {
  if (identical(modular, "auto")) {
    return(is_grid(structure))
  }
  if (!rlang::is_bool(modular)) {
    abort_bayesbem("{.arg modular} must be {.code TRUE}, {.code FALSE} or {.val auto}, not {describe_value(modular)}.",
                   "argument", call = call)
  }
  if (modular && !is_grid(structure)) {
    abort_bayesbem(c("The modular fit needs a grid design: every simulation run at every field input.",
                     i = "Use {.code modular = FALSE}, or run the simulator at the field inputs (see {.fn simulate_design})."),
                   "argument", call = call)
  }
  modular
}

# The path calibrate() takes on `data` by default, in words.
default_path <- function(data) {
  if (is.null(data$grid)) {
    return(sprintf("the dense joint likelihood (the runs are not at every field input), %d x %d per gradient",
                   data$n + data$m, data$n + data$m))
  }
  emulator <- choose_emulator("auto", TRUE, data)
  sprintf("the grid likelihood in two stages, the %s emulator", emulator)
}

# What a fit costs: seconds per gradient per cubed row of the matrix it
# factors, by likelihood (bench/results/scaling.md for the dense one,
# "Gradient cost" at n = 365 for the joint grid's field block and stage
# 2's, and by hour for the additive discrepancy's factor of its basis
# functions and components), and gradients per iteration (7e4 in a
# default joint fit of 4000 iterations, "Scaling").
fit_cost <- list(seconds_per_cubed_row = c(dense = 1.2e-9, grid = 6.7e-10, stage2 = 1.6e-10,
                                           additive = 4.7e-10),
                 gradients_per_iteration = 17.5)

# Taking the dense likelihood because the runs are not a grid is slow
# above a few hundred rows: say why, what it costs, how to avoid it.
inform_dense <- function(data, structure, asked) {
  if (is_grid(structure) || asked == "dense") {
    return(invisible())
  }
  rows <- data$n + data$m
  iterations <- default_sampling(FALSE, data$n)$iter
  seconds <- fit_cost$gradients_per_iteration * iterations *
    fit_cost$seconds_per_cubed_row[["dense"]] * rows^3
  hours <- seconds / 3600
  if (hours < 0.1) {
    return(invisible())
  }
  cli::cli_inform(c("!" = "The runs are not at every field input, so {.fn calibrate} uses the dense likelihood: a {rows} x {rows} factor per gradient, about {signif(hours, 1)} hour{?s} of sampling per chain.",
                    i = "Run every setting at the field inputs (a simulator of the field's periods in {.fn simulate_design}) for the grid likelihood, seconds to minutes; {.fn koh_data} matches inputs within 5% of their range."),
                  class = "bayesbem_message_dense")
}

# What one chain's likelihood holds and costs: `bytes`, the matrices of a
# gradient (the n x n ones the field rows' covariance needs, or for the
# dense likelihood the (n + m)^2 covariance of field and runs, whose Stan
# autodiff keeps about 64 bytes per element, and its squared distances,
# p + q + 4 doubles per pair), and `hours` of sampling `iter` iterations
# (fit_cost).
fit_size <- function(data, structure, modular, iter, discrepancy_kernel = "product") {
  n <- vapply(output_data(data), `[[`, integer(1), "n")
  if (discrepancy_kernel == "additive") {
    # a factor of each output's basis functions and components, whatever the rows
    p <- vapply(output_data(data), `[[`, integer(1), "p")
    rows <- hsgp_design()$m * p + 10L
    bytes <- sum(8 * n * rows + 8 * 6 * rows^2)
    seconds <- fit_cost$gradients_per_iteration * iter *
      fit_cost$seconds_per_cubed_row[["additive"]] * sum(rows^3)
    return(list(bytes = bytes, hours = seconds / 3600, rows = max(rows)))
  }
  if (!is_grid(structure)) {
    rows <- data$n + data$m
    bytes <- (64 + 8 * (data$p + data$q + 4)) * rows^2
  } else {
    rows <- n
    n_x <- vapply(output_data(data), function(d) d$grid$n_x, integer(1))
    # field block: data, kernel, covariance and its inverse; joint grid: Kx too
    bytes <- sum(8 * 6 * n^2) + if (modular) 0 else sum((64 + 8 * (data$p + 2)) * n_x^2)
  }
  path <- if (!is_grid(structure)) "dense" else if (modular) "stage2" else "grid"
  seconds <- fit_cost$gradients_per_iteration * iter * fit_cost$seconds_per_cubed_row[[path]] *
    sum(rows^3)
  list(bytes = bytes, hours = seconds / 3600, rows = max(rows))
}

# calibrate()'s check before any fit: each output's measured total inside
# its runs' totals (grid designs, where every run is at every field row).
check_prior_covers <- function(data, call = rlang::caller_env()) {
  outputs <- output_data(data)
  for (k in seq_along(outputs)) {
    d <- outputs[[k]]
    if (is.null(d$grid)) next
    totals <- prior_totals(d)
    range <- range(totals$runs)
    if (totals$measured >= range[1] && totals$measured <= range[2]) next
    label <- if (length(outputs) > 1L) sprintf(" of output %s", names(outputs)[k]) else ""
    abort_bayesbem(c("The measured total{label} lies outside every run's total over the same periods: no setting the runs span reaches it.",
                     x = "Measured {format(signif(totals$measured, 4))}; the {length(totals$runs)} runs give {format(signif(range[1], 4))} to {format(signif(range[2], 4))}.",
                     i = "Check the units and the building's size ({.fn bem_building_facts}), widen the parameters' ranges and rerun the design; calibrating would leave the whole gap to the discrepancy."),
                   "prior_misses", call = call)
  }
  invisible()
}

# A fit that cannot fit in memory, or would sample for longer than
# `getOption("bayesbem.max_hours", 24)` per chain, is refused before
# anything runs, saying what it would need and what to do. `parallel`:
# the chains run at once, each holding its own matrices.
check_fit_size <- function(size, parallel, available = available_memory(),
                           call = rlang::caller_env()) {
  max_hours <- getOption("bayesbem.max_hours", 24)
  needed <- size$bytes * parallel
  memory_ok <- is.na(available) || needed <= 0.8 * available
  if (memory_ok && size$hours <= max_hours) {
    return(invisible())
  }
  gb <- function(b) format(signif(b / 2^30, 2))
  abort_bayesbem(c("This fit is too large to run here: its likelihood factors a {size$rows} x {size$rows} matrix per gradient.",
                   x = "It would need about {gb(needed)} GB of memory ({parallel} chain{?s} at once){if (!is.na(available)) paste0(', of ', gb(available), ' GB available')} and about {format(signif(size$hours, 2))} hours of sampling per chain (limit {max_hours}: {.code options(bayesbem.max_hours = )}).",
                   i = "Calibrate on fewer rows: daily or weekly sums ({.code bem_simulator(by = \"day\")}), or a few weeks of the periods; run fewer chains at once ({.arg cores}).",
                   i = "Or, with the basis emulator, use {.code discrepancy_kernel = \"additive\"}: its gradient costs the same at any number of rows."),
                 "too_large", call = call)
}

# The memory the system has available (bytes), NA where unknown.
available_memory <- function() {
  info <- tryCatch(readLines("/proc/meminfo", warn = FALSE), error = function(e) character(0))
  line <- grep("^MemAvailable:", info, value = TRUE)
  if (length(line) == 0L) {
    return(NA_real_)
  }
  as.numeric(gsub("[^0-9]", "", line)) * 1024
}

# discrepancy_kernel = "auto": where both kernels apply (the basis
# emulator, periods of one length within each output) their posteriors and
# held-out intervals agree (bench/results/discrepancy-kernel.md, from 50
# training days up), so the one whose fit costs less (fit_size() at the
# defaults' iterations): the product's factor grows as n^3 in the rows,
# the additive one's is of its basis functions and components at any n
# (R/gp-hsgp.R). Elsewhere the paper's product kernel.
choose_discrepancy_kernel <- function(kernel, emulator, data, call = rlang::caller_env()) {
  unequal <- vapply(output_data(data), function(d) diff(range(noise_weights(d))) > 1e-12,
                    logical(1))
  if (kernel == "auto") {
    both <- emulator == "basis" && !any(unequal)
    return(if (both && additive_cheaper(data)) "additive" else "product")
  }
  if (kernel != "additive") {
    return("product")
  }
  if (emulator != "basis") {
    abort_bayesbem(c("The additive discrepancy needs the basis emulator.",
                     i = "Use {.code emulator = \"basis\"} (a modular fit on a grid design)."),
                   "argument", call = call)
  }
  if (any(unequal)) {
    abort_bayesbem(c("The additive discrepancy needs periods of one length in each output.",
                     i = "The field's {.field days} differ between rows; use {.code discrepancy_kernel = \"product\"}."),
                   "argument", call = call)
  }
  "additive"
}

# The additive discrepancy's fit predicted to cost less than the product's,
# each at its default iterations (a modular fit on a grid).
additive_cheaper <- function(data) {
  hours <- vapply(c("additive", "product"), function(kernel) {
    iter <- default_sampling(TRUE, largest_output(data), "basis", kernel)$iter
    fit_size(data, "grid", TRUE, iter, kernel)$hours
  }, numeric(1))
  hours[["additive"]] < hours[["product"]]
}

# noise_correlation = "auto": "ar1" where it applies, the additive
# discrepancy over rows with times of which some follow one another (meter
# data: their residuals persist); AR(1) holds white noise at phi = 0, its
# cost and the months' intervals with either noise: bench/results/year-hours.md.
# Elsewhere "none" (the paper's). "ar1" needs the additive
# discrepancy (its likelihood reads the rows through Gram matrices, which
# the AR(1) precision keeps tridiagonal) and the field rows' times
# (field_segments()).
choose_noise_correlation <- function(correlation, kernel, data, call = rlang::caller_env()) {
  if (correlation == "auto") {
    consecutive <- function(d) {
      segments <- data_segments(d)
      !is.null(segments) && anyDuplicated(segments) > 0L
    }
    ar1 <- kernel == "additive" && all(vapply(output_data(data), consecutive, logical(1)))
    return(if (ar1) "ar1" else "none")
  }
  if (correlation != "ar1") {
    return("none")
  }
  if (kernel != "additive") {
    abort_bayesbem(c("AR(1) noise needs the additive discrepancy.",
                     i = "Use {.code discrepancy_kernel = \"additive\"} (with the basis emulator)."),
                   "argument", call = call)
  }
  "ar1"
}

# noise_shift = "auto": "month" for the additive discrepancy over rows
# with times, in at least three months and with more rows than months
# (meter data by the hour or day); "none" elsewhere (bills: a shift per
# bill would be the noise itself). "month" needs the additive discrepancy
# (its likelihood takes the months as basis columns) and the rows' times.
choose_noise_shift <- function(shift, kernel, data, call = rlang::caller_env()) {
  if (shift == "auto") {
    monthly <- function(d) {
      times <- data_times(d)
      if (is.null(times)) {
        return(FALSE)
      }
      months <- period_months(times)
      length(unique(months)) >= 3L && length(months) > 2 * length(unique(months))
    }
    month <- kernel == "additive" && all(vapply(output_data(data), monthly, logical(1)))
    return(if (month) "month" else "none")
  }
  if (shift == "month" && kernel != "additive") {
    abort_bayesbem(c("A shift per month needs the additive discrepancy.",
                     i = "Use {.code discrepancy_kernel = \"additive\"} (with the basis emulator)."),
                   "argument", call = call)
  }
  shift
}

# emulator = "auto": the basis emulator for a modular fit of more than 36
# field rows (see the @param); "basis" needs a modular fit. Returns
# "separable", "basis", or "none" for a joint fit.
choose_emulator <- function(emulator, modular, data, call = rlang::caller_env()) {
  if (!modular) {
    if (emulator == "basis") {
      abort_bayesbem(c("The basis emulator needs a modular fit.",
                       i = "Use {.code modular = TRUE} (or {.val auto}) on a grid design: every simulation run at every field input."),
                     "argument", call = call)
    }
    return("none")
  }
  if (emulator == "auto") {
    return(if (largest_output(data) > 36L) "basis" else "separable")
  }
  emulator
}

# Sampler control: the user's entries over the defaults, each one known to
# rstan (an unknown one would be ignored without a word).
merge_control <- function(control, defaults, call = rlang::caller_env()) {
  if (is.null(control)) {
    return(defaults)
  }
  if (!is.list(control) || (length(control) > 0L && !rlang::is_named(control))) {
    abort_bayesbem("{.arg control} must be a named list such as {.code list(adapt_delta = 0.95)}, not {describe_value(control)}.",
                   "argument", call = call)
  }
  unknown <- setdiff(names(control), control_arguments())
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg control} has {cli::qty(length(unknown))}entr{?y/ies} {.field {unknown}} that {.fn rstan::sampling} does not know.",
                     i = "Its entries are {.field {control_arguments()}}; check the spelling."),
                   "argument", call = call)
  }
  utils::modifyList(defaults, control)
}

control_arguments <- function() {
  c("adapt_engaged", "adapt_gamma", "adapt_delta", "adapt_kappa", "adapt_t0",
    "adapt_init_buffer", "adapt_term_buffer", "adapt_window", "max_treedepth", "metric",
    "stepsize", "stepsize_jitter")
}

# `calibrate(adapt_delta = 0.99)`: say where such an entry goes.
check_control_misplaced <- function(dots, call = rlang::caller_env()) {
  misplaced <- intersect(names(dots), control_arguments())
  n <- length(misplaced)
  if (n > 0L) {
    example <- sprintf("control = list(%s = %s)", misplaced[1], format(dots[[misplaced[1]]]))
    abort_bayesbem(c("{.arg {misplaced}} {cli::qty(n)}{?is a/are} sampler control entr{?y/ies}, not {?an argument/arguments} of {.fn calibrate}.",
                     i = "Give {cli::qty(n)}{?it/them} in {.arg control}: {.code {example}}."),
                   "argument", call = call)
  }
}

# Chains run at once by default: every core, or two under R CMD check's
# limit (_R_CHECK_LIMIT_CORES_), as CRAN asks of examples and tests.
default_cores <- function() {
  n <- parallel::detectCores()
  if (is.na(n) || n < 1L) n <- 1L
  if (nzchar(Sys.getenv("_R_CHECK_LIMIT_CORES_"))) n <- min(n, 2L)
  as.integer(n)
}

# The rstan::sampling() arguments calibrate() passes on through `...` (it sets
# the others itself).
sampling_arguments <- function() {
  c("init", "init_r", "refresh", "thin", "save_warmup", "sample_file", "diagnostic_file",
    "verbose", "check_data", "show_messages", "enable_random_init")
}

# Stan stops when a Cholesky factor fails at every initial value; Stan only
# says "Matrix m is not positive definite". Name the matrix: the emulator's
# correlation factors are tried at long length scales (rho up to 0.999),
# where they are closest to singular.
abort_sampling_failure <- function(data, nugget, structure, messages, call = rlang::caller_env()) {
  factors <- list("the correlation of the field inputs (K_x)" = data$xf)
  if (is_grid(structure)) {
    factors[["the correlation of the simulation runs (K_t)"]] <- data$grid$design
  } else {
    factors[["the correlation of the simulation rows"]] <- cbind(data$xc, data$tc)
  }
  singular <- names(factors)[vapply(factors, function(u) {
    pair <- pair_geometry(u, u)
    any(vapply(c(0.9, 0.99, 0.999), function(rho) {
      inherits(try(chol(jittered_cor(pair, rep(-4 * log(rho), ncol(u)), nugget)), silent = TRUE),
               "try-error")
    }, logical(1)))
  }, logical(1))]
  if (length(singular) == 0L) {
    # Stan's lines are shown as they are (cli would interpolate their braces)
    said <- gsub("}", "}}", gsub("{", "{{", messages, fixed = TRUE), fixed = TRUE)
    abort_bayesbem(c("Stan could not sample the model. Its last messages:",
                     stats::setNames(said, rep(" ", length(said)))),
                   "sampling", call = call)
  }
  abort_bayesbem(c("Stan could not sample the model: the Cholesky factor of {singular[1]} failed.",
                   x = "With {.code nugget = {nugget}} it is not positive definite at long length scales.",
                   i = "Raise {.arg nugget} in {.fn koh_priors} (e.g. {.code koh_priors(nugget = 1e-4)}), or drop nearly identical rows."),
                 "cholesky", call = call)
}

# Calibrates again with the fit's data, priors and sampler settings; `...`
# replaces any argument of calibrate().
refit <- function(fit, ...) {
  settings <- fit$settings
  args <- list(field = fit$data, priors = fit$priors, chains = settings$chains, iter = settings$iter,
               warmup = settings$warmup, seed = settings$seed, control = settings$control,
               structure = settings$structure %||% "auto", modular = isTRUE(settings$modular),
               emulator = if (isTRUE(settings$modular)) settings$emulator %||% "separable" else "auto",
               discrepancy_kernel = settings$discrepancy_kernel %||% "product",
               noise_correlation = settings$noise_correlation %||% "none",
               noise_shift = settings$noise_shift %||% "none",
               minor_modes = settings$minor_modes %||% "keep",
               covariates = fit_covariates(fit))
  # replaced whole, not merged: a new bayesbem_data or priors is a list too
  changes <- list(...)
  args[names(changes)] <- changes
  do.call(calibrate, args)
}

# A fit's discrepancy terms as calibrate() takes them: a table, or on
# several outputs a list of tables by output (those with terms).
fit_covariates <- function(fit) UseMethod("fit_covariates")

fit_covariates.bayesbem_fit <- function(fit) fit$data$covariates

fit_covariates.bayesbem_fit_outputs <- function(fit) {
  terms <- Filter(Negate(is.null), lapply(fit$data$outputs, `[[`, "covariates"))
  if (length(terms) > 0L) terms
}
