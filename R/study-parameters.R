#' Study the number of calibration parameters
#'
#' The parameter study of Chong and Menberg (2018): calibrate with the `k`
#' highest-ranked parameters, for each `k`, and compare each parameter's
#' posterior across `k`. The paper's Fig 4 shows what it finds: every added
#' parameter costs the others posterior precision, because the same data
#' must now inform more unknowns.
#'
#' With a simulator, each `k` gets its own Latin-hypercube design of
#' `n_runs` runs over the top `k` parameters, the others held at their
#' initial values ([design_lhs()], [simulate_design()]), and the field data's
#' observable inputs must be the simulator's. With a simulation table (what
#' the paper's public data are), the `k`-parameter calibration uses the
#' table's first `k` ranked parameter columns and ignores the others, whose
#' variation then acts as emulator noise.
#'
#' Fits run through [future.apply::future_lapply()]: sequentially by
#' default, in parallel with a [future::plan()] (give each fit `cores = 1`
#' then). Simulation runs go through [simulate_design()], which uses the same
#' plan. Progress is reported through progressr: wrap the call in
#' [progressr::with_progress()].
#'
#' @param field A [koh_data()] object (with a simulation table), or the
#'   field data frame: the output, then the observable inputs.
#' @param sim A `bayesbem_simulator` ([bem_simulator()],
#'   [eplus_simulator()]), or a simulation table `[eta, x, t]`.
#' @param ranking Parameter names from most to least influential, or a
#'   Morris screening from [screen_morris()]. Defaults to the simulation
#'   table's parameter columns in order.
#' @param k Numbers of parameters to calibrate.
#' @param n_runs Runs per design (with a simulator).
#' @param newdata,obs Optional held-out data: a data frame with the
#'   observable inputs, and the measured output of each of its rows.
#' @param priors A [koh_priors()] object; calibration-parameter priors it
#'   gives for parameters outside a fit's top `k` are dropped for that fit.
#' @param seed Random seed of the designs and of every fit.
#' @template args-ndraws
#' @param ... Further arguments to [calibrate()], e.g. `chains`, `iter`,
#'   `cores`.
#' @return An object of class `bayesbem_parameter_study`: a list with `fits` (a
#'   `bayesbem_fit` per `k`, named `"k = 2"`, ...; printing and plotting do not
#'   need them, set to `NULL` to store a small study), `k`, `ranking`,
#'   `posteriors` (one row per `k`
#'   and parameter: `mean`, `sd`, quantiles `q5` to `q95` in physical
#'   units, `scaled` median on \[0, 1\]) and `metrics` (CVRMSE and NMBE per
#'   `k` and data set). Plot it with [plot_parameter_study()].
#' @family studies
#' @export
#' @examples
#' \donttest{
#' study <- study_parameters(seb_field, seb_sim, k = 1:3, chains = 1, iter = 300,
#'                           refresh = 0)
#' study
#' plot(study)
#' }
study_parameters <- function(field, sim = NULL, ranking = NULL, k = 2:6, n_runs = 30L,
                             newdata = NULL, obs = NULL, priors = koh_priors(), seed = 2018L,
                             ndraws = NULL, ...) {
  check_count(n_runs)
  if (inherits(sim, "bayesbem_simulator")) {
    ranking <- study_ranking(ranking, sim$parameters$parameter, k)
    tables <- lapply(k, function(kk) {
      params <- sim$parameters[match(ranking[seq_len(kk)], sim$parameters$parameter), ]
      simulate_design(sim, design_lhs(params, n = n_runs, seed = seed))
    })
    if (inherits(field, "bayesbem_data")) field <- field_table(field)
    datasets <- lapply(tables, function(runs) koh_data(field, runs))
  } else {
    data <- as_koh_data(field, sim)
    ranking <- study_ranking(ranking, data$names$t, k)
    cols <- data$names
    datasets <- lapply(k, function(kk) {
      koh_data(field_table(data),
               data$sim[c(cols$eta, cols$x_sim, ranking[seq_len(kk)])])
    })
  }
  check_held_out(newdata, obs, datasets[[1]])
  jobs <- lapply(datasets, function(d) {
    kept <- priors
    kept$tf <- priors$tf[intersect(names(priors$tf), d$names$t)]
    list(field = d, priors = kept, seed = seed, ...)
  })
  names(jobs) <- paste("k =", k)
  fits <- run_fits(jobs)
  structure(list(fits = fits, k = k, ranking = ranking,
                 posteriors = study_posteriors(fits, "k"),
                 metrics = study_metrics(fits, "k", newdata, obs, ndraws)),
            class = "bayesbem_parameter_study")
}

# The ranked parameter names, checked against those available and `k`.
study_ranking <- function(ranking, available, k, call = rlang::caller_env()) {
  if (inherits(ranking, "bayesbem_morris")) {
    ranking <- unique(ranking$parameter[order(ranking$rank)])
  }
  ranking <- ranking %||% available
  if (!is.character(ranking) || anyDuplicated(ranking)) {
    abort_bayesbem(c("{.arg ranking} must be distinct parameter names, or a Morris screening.",
                     i = "E.g. {.code screen_morris(sim)}, or {.code c(\"equipment_power_density\", ...)}."),
                   "argument", call = call)
  }
  unknown <- setdiff(ranking, available)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg ranking} names unknown parameter{?s} {.field {unknown}}.",
                     i = "Available: {.field {available}}."),
                   "argument", call = call)
  }
  if (!is.numeric(k) || length(k) == 0L || any(k != round(k)) || any(k < 1) ||
      any(k > length(ranking)) || anyDuplicated(k)) {
    abort_bayesbem(c("{.arg k} must be distinct whole numbers from 1 to {length(ranking)}, the number of ranked parameters.",
                     x = "It is {.val {k}}."),
                   "argument", call = call)
  }
  ranking
}

#' @export
print.bayesbem_parameter_study <- function(x, digits = 3, ...) {
  rlang::check_dots_empty()
  print_study(x, "k", "{.cls bayesbem_parameter_study}: top k = {x$k} of {.field {x$ranking}}", digits)
}
