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
#' A joint `koh_fit` (`modular = FALSE`: every hyperparameter sampled) of
#' [seb_field] and [seb_sim] with the default priors (2 chains of 400
#' iterations, seed 2018), shipped so that examples run in seconds. Too
#' short for conclusions: it has not converged for every hyperparameter
#' (see [check_convergence()]); calibrate with more iterations for real
#' work.
#'
#' @format A `koh_fit` (see [calibrate()]).
#' @source Built by `data-raw/seb_fit.R`.
#' @family case study
#' @examples
#' seb_fit
#' predict(seb_fit, ndraws = 50)
"seb_fit"
