#' Case study: field data of the NREL site entrance building
#'
#' Twelve months (January to December 2013) of measured electricity use of a
#' 79 m2 single-storey building in Golden, Colorado (the case study of Chong
#' and Menberg 2018), with the monthly weather that drives it.
#'
#' @format A data frame with 12 rows (months, January first) and 5 columns:
#' \describe{
#'   \item{y}{measured monthly electricity use (kWh)}
#'   \item{temp}{monthly mean outdoor dry-bulb temperature (degrees C)}
#'   \item{rh}{monthly mean outdoor relative humidity (percent)}
#'   \item{solar}{monthly mean direct solar radiation rate per area (W/m2)}
#'   \item{month}{the first day of the month (`Date`); [koh_data()] takes it
#'     as the rows' period, not as an input}
#' }
#' `temp` and `rh` are exactly the monthly means of the 2013 weather file
#' shipped as `system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")`;
#' `solar` is within about 2 percent of that file's monthly mean direct normal
#' radiation (EnergyPlus's site direct solar radiation rate per area).
#' @source `DATAFIELD.csv` of the bc-stan repository (MIT licence, (c) 2018
#'   Adrian Chong; see the file `COPYRIGHTS` of this package), renamed
#'   columns; built by `data-raw/seb.R`.
#' @family case study
#' @examples
#' seb_field
"seb_field"

#' Case study: held-out bills of January-June 2012
#'
#' Six more measured monthly bills of the meter of [seb_field], a year
#' earlier, with the monthly weather of those months: the out-of-sample test
#' of Chong and Menberg (2018, Table 3). Calibrate on `seb_field` (2013),
#' predict these months, compare. The 2012 months lie partly outside the
#' 2013 weather, so the emulator extrapolates there; [predict_scenario()]
#' reruns the simulator at their weather instead.
#'
#' @format A data frame with 6 rows (months, January first) and 7 columns:
#' \describe{
#'   \item{y}{measured electricity use of the billing period (kWh)}
#'   \item{temp, rh, solar}{monthly means of the 2012 weather file
#'     `system.file("extdata", "2012_AMY.epw.gz", package = "bayesbem")`:
#'     dry-bulb temperature (degrees C), relative humidity (percent), direct
#'     normal radiation (W/m2), as [epw_monthly()] computes them}
#'   \item{month}{the first day of the calendar month (`Date`)}
#'   \item{bill_start, bill_end}{the billing period, inclusive, as the
#'     utility data give it: the January bill ends on the 30th, the
#'     February one on the 28th (2012 is a leap year)}
#' }
#' January 2012 (1031 kWh) lies far below every other month of both years;
#' the source does not explain it. Report held-out figures with and without
#' it.
#' @source NREL's public OpenStudio analysis examples: the utility data of
#'   the site entrance building (`tot_kwh` by billing period), the series
#'   whose 2013 values equal `seb_field$y`. Built by `data-raw/seb_holdout.R`.
#' @family case study
#' @examples
#' seb_holdout
#' # the weather of 2012 against the range of the 2013 runs
#' range(seb_sim$rh)
#' seb_holdout$rh
"seb_holdout"

#' Case study: EnergyPlus simulation runs of the NREL site entrance building
#'
#' The simulation design of the case study of Chong and Menberg (2018): 10
#' settings of the three most influential uncertain parameters, each
#' simulated with EnergyPlus over the 12 field months.
#'
#' @format A data frame with 120 rows (rows 1-12 are setting 1, January to
#' December; rows 13-24 setting 2; and so on) and 7 columns:
#' \describe{
#'   \item{eta}{simulated monthly electricity use (kWh)}
#'   \item{temp, rh, solar}{the observable inputs of [seb_field], repeated
#'     for each setting}
#'   \item{fan_total_efficiency}{fan total efficiency (fraction)}
#'   \item{equipment_power_density}{electric equipment power density (W/m2)}
#'   \item{infiltration_per_exterior_area}{infiltration flow rate per
#'     exterior surface area (m3/s per m2)}
#' }
#' @source `DATACOMP.csv` of the bc-stan repository (MIT licence, (c) 2018
#'   Adrian Chong; see the file `COPYRIGHTS` of this package), renamed
#'   columns; built by `data-raw/seb.R`.
#' @family case study
#' @examples
#' head(seb_sim)
"seb_sim"

#' Case study: a small example calibration
#'
#' A joint `bayesbem_fit` (`modular = FALSE`: every hyperparameter sampled) of
#' [seb_field] and [seb_sim] with the default priors (2 chains of 400
#' iterations, seed 2018), shipped so that examples run in seconds. Too
#' short for conclusions: it has not converged for every hyperparameter
#' (see [check_convergence()]); calibrate with more iterations for real
#' work.
#'
#' @format A `bayesbem_fit` (see [calibrate()]).
#' @source Built by `data-raw/seb_fit.R`.
#' @family case study
#' @examples
#' seb_fit
#' predict(seb_fit, ndraws = 50)
"seb_fit"
