#' Hourly energy use of the embedded building model (ISO 13790, 5R1C)
#'
#' The simple hourly method of ISO 13790 (Annex C; ISO 52016-1's
#' predecessor): one thermal zone as a network of five resistances and one
#' capacity, the building of [bem_monthly()] with the same parameters, so
#' that hourly, daily and bill-period data can be simulated without
#' EnergyPlus. Each hour, with the conductances of [bem_monthly()]:
#'
#' * nodes: air `theta_air`, surfaces `theta_s` and mass `theta_m`; the
#'   mass area `A_m = 2.5 A_floor`, the surfaces' `A_t = 4.5 A_floor`,
#'   `H_tr_is = 3.45 A_t`, `H_tr_ms = 9.1 A_m`, the windows' `H_tr_w` and
#'   the opaque elements' `H_tr_em = 1 / (1 / H_tr_op - 1 / H_tr_ms)`;
#'   ventilation `H_ve` at outdoor temperature;
#' * gains: half the internal gains to the air; the other half and the
#'   solar gains (`I_vert` as in [bem_monthly()], hourly) split between
#'   the mass (`A_m / A_t`) and the surfaces (`1 - A_m / A_t - H_tr_w /
#'   (9.1 A_t)`);
#' * the mass temperature steps by Crank-Nicolson (ISO 13790 C.4), the heat
#'   capacity `C_m` of [bem_monthly()];
#' * heating or cooling power (unlimited, on the air node) where the free
#'   air temperature leaves the set points, just enough to hold it at
#'   the set point (C.4.2: the air temperature is linear in that power);
#'   the heating's set point follows the building's `heating_schedule`
#'   (off hours at its `heating_setback`), so that a plant on a timer
#'   reheats the cooled building each morning.
#'
#' Lights and equipment follow the building's `occupancy` by hour of week,
#' on its `clock` and with its `holidays` ([bem_building()])
#' (`base + (1 - base) * occupancy`, `base` chosen so that the mean is the
#' monthly model's `lighting_fraction` and `equipment_fraction`), and so do
#' the occupants' gains (mean `occupant_gain`); the fan runs continuously.
#' The meters follow as in [bem_monthly()], hour by hour. The first day is
#' simulated seven times before the first hour counts (warm-up, as
#' EnergyPlus repeats its first day). Its monthly totals and those of
#' [bem_monthly()] agree within the tolerance `test-sim-bem-hourly.R`
#' states.
#'
#' @param parameters A named list or one-row data frame with all 14
#'   parameters of [bem_parameters()] (physical units).
#' @param weather Hourly weather from `epw_weather(by = "hour")` (columns
#'   `temp`, `dni`, `dhi`, `ghi`, `hour`, `weekday`, and `time` for a
#'   building with a `clock` or `holidays`), in time order.
#' @param building Building properties from [bem_building()].
#' @return A data frame with one row per hour: `electricity` and `gas`
#'   (kWh), the needs `heating_need` and `cooling_need` (kWh) and the air
#'   temperature `air_temp` (degrees C).
#' @family simulation
#' @export
#' @examples
#' p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
#' w <- epw_weather(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"),
#'                  by = "hour")
#' h <- bem_hourly(p, w)
#' head(h)
#' # monthly sums beside the monthly model
#' cbind(hourly = tapply(h$gas, w$month, sum), monthly = bem_monthly(p, epw_monthly(
#'   system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")))$gas)
bem_hourly <- function(parameters, weather, building = bem_building()) {
  k <- bem_constants(parameters, building)
  p <- k$p
  b <- building
  week_hour <- schedule_hours(weather, b)
  occupancy <- b$occupancy / max(mean(b$occupancy), .Machine$double.eps)
  lights <- k$lights * schedule_shape(b$occupancy, b$lighting_fraction)[week_hour]
  equipment <- k$equipment * schedule_shape(b$occupancy, b$equipment_fraction)[week_hour]
  internal <- lights + equipment + k$occupants * occupancy[week_hour] + k$fan_heat
  # an uncooled building's air floats above the cooling set point
  cooling_setpoint <- if (isTRUE(b$cooling %||% TRUE)) p$cooling_setpoint else Inf
  hvac <- network_hours(k, b$floor_area, weather$temp, internal, k$solar(weather),
                        heating_setpoints(p$heating_setpoint, b)[week_hour], cooling_setpoint)
  out <- bem_meters(k, pmax(hvac$power, 0), pmax(-hvac$power, 0), lights + equipment + k$p_fan, 1)
  out$air_temp <- hvac$air
  out
}

# A use's profile over the 168 hours of a week, mean 1: a base share
# while unoccupied, full use while occupied, the base chosen so that the
# mean share of full use is `fraction` (the monthly model's constant).
schedule_shape <- function(occupancy, fraction) {
  m <- mean(occupancy)
  base <- if (m >= 1) 1 else min(max((fraction - m) / (1 - m), 0), 1)
  profile <- base + (1 - base) * occupancy
  profile / mean(profile)
}

# The 5R1C network (ISO 13790 Annex C) hour by hour: the heating (> 0) or
# cooling (< 0) power on the air node that holds the air between the set
# points (the heating's one per hour), and the air temperature. `internal`
# and `solar` gains in W.
network_hours <- function(k, floor_area, temp, internal, solar, heating_setpoint,
                          cooling_setpoint) {
  a_m <- 2.5 * floor_area
  a_t <- 4.5 * floor_area
  h_is <- 3.45 * a_t
  h_ms <- 9.1 * a_m
  h_w <- k$h_tr_w
  h_em <- 1 / (1 / k$h_tr_op - 1 / h_ms)
  h_ve <- k$h_ve
  h_1 <- 1 / (1 / h_ve + 1 / h_is)
  h_2 <- h_1 + h_w
  h_3 <- 1 / (1 / h_2 + 1 / h_ms)
  cm <- k$c_m / 3600
  # gains to the air, the surfaces and the mass (C.2)
  phi_ia <- 0.5 * internal
  phi_m <- a_m / a_t * (0.5 * internal + solar)
  phi_st <- (1 - a_m / a_t - h_w / (9.1 * a_t)) * (0.5 * internal + solar)
  # one hour from the mass temperature `tm` with power `phi` on the air (C.4)
  step <- function(i, tm, phi) {
    te <- temp[i]
    total <- phi_m[i] + h_em * te + h_3 * (phi_st[i] + h_w * te + h_1 * ((phi_ia[i] + phi) / h_ve + te)) / h_2
    tm_next <- (tm * (cm - 0.5 * (h_3 + h_em)) + total) / (cm + 0.5 * (h_3 + h_em))
    m <- (tm + tm_next) / 2
    s <- (h_ms * m + phi_st[i] + h_w * te + h_1 * (te + (phi_ia[i] + phi) / h_ve)) / (h_ms + h_w + h_1)
    c(tm_next, (h_is * s + h_ve * te + phi_ia[i] + phi) / (h_is + h_ve))
  }
  # the power that holds the air at the set point it would leave: the air
  # temperature is linear in it, so a trial at 10 W/m2 finds it (C.4.2)
  hour <- function(i, tm) {
    free <- step(i, tm, 0)
    target <- min(max(free[2], heating_setpoint[i]), cooling_setpoint)
    if (target == free[2]) {
      return(c(free, 0))
    }
    trial <- 10 * floor_area
    slope <- (step(i, tm, trial)[2] - free[2]) / trial
    phi <- (target - free[2]) / slope
    c(step(i, tm, phi), phi)
  }
  n <- length(temp)
  tm <- heating_setpoint[1]
  for (warm in seq_len(7)) {
    for (i in seq_len(min(24L, n))) tm <- hour(i, tm)[1]
  }
  power <- air <- numeric(n)
  for (i in seq_len(n)) {
    out <- hour(i, tm)
    tm <- out[1]
    air[i] <- out[2]
    power[i] <- out[3]
  }
  list(power = power, air = air)
}
