#' Field and simulation data for a KOH calibration
#'
#' Combines measured (field) data and simulation runs in the layout of Chong
#' and Menberg (2018), checks them, and scales them as the method requires.
#'
#' The field table holds the measured output `y` and the `p` observable
#' inputs `x`. The simulation table holds the simulator output `eta`, the
#' same `p` inputs, and the `q` calibration parameters `t` of each run. The
#' outputs are named: by default the columns called `y` and `eta` (as
#' [simulate_field()] and [simulate_design()] write them; `eta` may also
#' carry the field output's name), else give `y` and `eta` (the paper's
#' files: `y = "yf", eta = "yc"`); a table without them is an error that
#' lists its columns. `x` is every other field column, matched in `sim` by
#' name, and `t` every other simulation column.
#' An input in one table but not the other is an error, and so is a
#' simulation column taken for a parameter that behaves like an input (one
#' value per input setting). Only when no field input name is in `sim` (the
#' paper's layout, `xf1` against `xc1`) are the simulation inputs taken by
#' position, after `eta`. Name the columns with `y`, `eta`, `x` and `t` to
#' choose them yourself.
#'
#' A logical `field` column `estimated` flags readings that were estimated,
#' not read (utilities mark them on the bill): those rows are left out,
#' with a message.
#'
#' Rows are periods, and two periods may share their inputs (two calm night
#' hours with the same weather, hour and weekday): each run then has a row
#' at each, and since the emulator takes the simulator as a function of the
#' inputs, those rows are averaged into one, with a message saying by how
#' much they differed (a state the inputs miss, such as the building's
#' stored heat, is then left to the discrepancy). More rows with the same
#' inputs and parameters than the field's periods there are a run
#' repeated, an error: average repeated runs first.
#'
#' Scaling (undone for every number shown to users):
#' * `y` and `eta` are standardised with the mean and standard deviation of
#'   `eta`;
#' * each `x` column is mapped to \[0, 1\] with its minimum and maximum over
#'   field and simulation rows together;
#' * each `t` column is put on its scale (`scales`) and then mapped to
#'   \[0, 1\] with its minimum and maximum over the simulation design.
#'
#' A parameter's scale is where the emulator works with it; its prior stays
#' in physical units (a flat prior is flat in the parameter itself, as in
#' the paper), by a change of variables in the Stan program. The emulator's
#' mean is linear in the parameters, and an output proportional to `1 / t`
#' (fan power against fan efficiency) is far from linear in `t`: the
#' emulator's error along that curve then leaves the posterior with several
#' modes. `scales = "auto"` (the default) puts a positive parameter on the
#' log or reciprocal scale when that lowers by at least a fifth the error
#' with which the least-squares fit of the runs' output on the inputs and
#' parameters (the emulator's mean) predicts each run left out, and keeps
#' the others as they are. Runs left out, not the fit's residuals: for a
#' parameter whose range reaches down to 0 (infiltration), such a scale
#' puts the run nearest 0 far from all others, where a fit to every run
#' matches it but the emulator has nothing to learn from. On the case
#' study it puts fan efficiency, whose fan power goes as its reciprocal, on
#' the reciprocal scale; what that does to convergence is measured in the
#' package's benchmarks (`bench/results/reliability.md`).
#' `scales = "identity"` is the paper's model.
#'
#' @section Noise of periods of different lengths: The observation noise
#'   is independent between rows, with variance `1 / lambda_e` (the paper's
#'   model). When the rows are periods of different lengths, an input
#'   `days` (as [bem_simulator()] and [eplus_simulator()] give it with the
#'   measurements' own `periods`), a period's total sums its days' errors,
#'   and each row's variance is `w_i / lambda_e` with `w_i = days_i /
#'   mean(days)` over the field rows: `1 / lambda_e` is then the noise of a
#'   period of the mean length, a 34-day bill's is `34 / 30.4` times as
#'   large as a 30.4-day bill's, and predictions of new periods with
#'   `noise = TRUE` weigh theirs the same way.
#' @section Several outputs: Field data and runs of several outputs (meters:
#'   electricity and gas bills, say) come as long tables with a column
#'   naming each row's output, `output` by default. Each output then gets a
#'   data set of its own, as above: its output standardised on its own
#'   (bills stay in their units), its own periods (a gas meter read on
#'   other days, a month without a bill) and its own grid; the outputs share
#'   the calibration parameters, their scales (with `scales = "auto"`, a
#'   parameter takes the scale the first output whose emulator gains by one
#'   chose) and the runs: every output needs the outputs of the same runs
#'   (one run gives every meter, as [simulate_design()] writes them), each
#'   at all of its field inputs. An output one table has and the other
#'   lacks is an error that names it.
#' @param field A data frame (or numeric matrix) of field data.
#' @param sim A data frame (or numeric matrix) of simulation runs.
#' @param y,eta Names of the output column in `field` and in `sim`; by
#'   default `"y"` and `"eta"` (or, in `sim`, the field output's name).
#' @param x Names of the observable-input columns, present in both tables.
#' @param t Names of the calibration-parameter columns in `sim`.
#' @param period Name of a `field` column of class `Date` or `POSIXct` that
#'   dates each row (e.g. the first day of each billing month). It is not an
#'   input: plots label the rows with it. By default the field's one such
#'   column, if it has one.
#' @param grid_tol Tolerance, on the scaled \[0, 1\] input scale, within
#'   which a simulation row's inputs count as a field row's. When every run
#'   has one row at each field input within this tolerance, the design is a
#'   grid: the simulation inputs are then taken to be the field inputs
#'   exactly, `print()` reports the largest difference, and [calibrate()]
#'   can use the fast grid likelihood. By default (`NULL`) rounding is
#'   matched (`1e-6`: tables written separately differ in the last digits),
#'   and failing that differences up to 5 % of each input's range, with a
#'   message naming them: field weather computed apart from the runs'
#'   (e.g. bills' months averaged from another copy of the weather file)
#'   differs by that much, and without the match the fit would take the
#'   dense likelihood, hours instead of seconds. Use `0` to require
#'   identical values.
#' @param scales `"auto"` (see Details), `"identity"` (every parameter as
#'   it is, as in the paper), or a named character vector giving some
#'   parameters `"identity"`, `"log"` or `"reciprocal"` (the others keep
#'   the identity), e.g. `c(fan_total_efficiency = "reciprocal")`. Reports
#'   and draws are always in physical units.
#' @param output Name of the column of both tables that names each row's
#'   output (see "Several outputs"); by default `"output"` when both tables
#'   have it, else there is one output.
#' @return An object of class `bayesbem_data`: the scaled matrices `y`, `eta`,
#'   `xf`, `xc`, `tc`, the column names, the sizes `n`, `m`, `p`, `q`, the
#'   `scaling` constants (with `days`, the field's mean period length, when
#'   the noise grows with it), and `grid`: the layout of the runs when every run
#'   was made at every field input, and possibly at further inputs such as
#'   those of held-out periods (`NULL` otherwise), which lets [calibrate()]
#'   use the fast Kronecker likelihood. With several outputs, an object of
#'   class `bayesbem_outputs`: `outputs`, the `bayesbem_data` of each output
#'   by name, and the names and scaling they share.
#' @family data preparation
#' @export
#' @examples
#' d <- koh_data(seb_field, seb_sim)
#' d
#' # the same by name
#' koh_data(seb_field, seb_sim, y = "y", eta = "eta", x = c("temp", "rh", "solar"),
#'          t = c("fan_total_efficiency", "equipment_power_density",
#'                "infiltration_per_exterior_area"))
koh_data <- function(field, sim, y = NULL, eta = NULL, x = NULL, t = NULL, period = NULL,
                     grid_tol = NULL, scales = "auto", output = NULL) {
  field <- without_estimated(as_numeric_table(field))
  sim <- as_numeric_table(sim)
  output <- outputs_column(field, sim, output)
  if (!is.null(output)) {
    args <- list(y = y, eta = eta, x = x, t = t, period = period, grid_tol = grid_tol,
                 scales = scales)
    return(koh_data_outputs(field, sim, output, args))
  }
  koh_data_one(field, sim, y, eta, x, t, period, grid_tol, scales)
}

# The field rows without those a logical column `estimated` flags (a bill
# the utility estimated, not read), said in a message; the column goes.
without_estimated <- function(field, call = rlang::caller_env()) {
  flag <- field$estimated
  if (is.null(flag)) {
    return(field)
  }
  if (!is.logical(flag) || anyNA(flag)) {
    abort_bayesbem(c("Column {.field estimated} of {.arg field} must be {.code TRUE} or {.code FALSE} in every row.",
                     x = "It is {describe_value(flag)}.",
                     i = "Flag the estimated readings {.code TRUE}, the others {.code FALSE}."),
                   "columns", call = call)
  }
  if (any(flag)) {
    cli::cli_inform(c(i = "Left out {sum(flag)} estimated reading{?s}: row{?s} {which(flag)} of {.arg field}."),
                    class = "bayesbem_message_estimated")
  }
  field[!flag, setdiff(names(field), "estimated"), drop = FALSE]
}

# `field` itself when it is a bayesbem_data or bayesbem_outputs object, else
# koh_data(field, sim).
as_koh_data <- function(field, sim) {
  if (inherits(field, c("bayesbem_data", "bayesbem_outputs"))) field else koh_data(field, sim)
}
