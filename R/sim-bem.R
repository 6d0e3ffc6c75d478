#' Uncertain parameters of the case-study building
#'
#' The 14 uncertain parameters of Chong and Menberg (2018), with their
#' initial values and ranges: the default parameter table of
#' [bem_simulator()], and the form [design_lhs()] and [screen_morris()]
#' take. A parameter table is a data frame with columns `parameter`,
#' `initial`, `min` and `max` (physical units); `unit` and `description` are
#' optional.
#'
#' With `type`, the loads (equipment and lighting power densities) start
#' and range around what the type of use implies ([bem_building_types()]):
#' at their initial values, in a building of that type
#' (`bem_building_facts(type = )`), the lighting is the type's ASHRAE
#' 90.1-2004 allowance and the two use the type's typical CIBSE TM46
#' electricity; the lighting ranges from half the allowance, or half the
#' benchmark's mean power where that is lower, to one and a half times the
#' allowance, the equipment from a tenth to one and a half times the
#' benchmark's mean power in use. The other parameters are the case
#' study's.
#'
#' A building that uses far more or less than its type's benchmark (a
#' laboratory wing, a data room, a half-empty block) lies outside those
#' ranges; `electricity`, its metered use per m2 of floor, takes the
#' benchmark's place, so that the loads start at and range around what the
#' meter says (the lighting allowance stays the type's; its lower limit
#' follows a meter below it, whose lights cannot draw more than the
#' meter).
#'
#' @param type A building type of [bem_building_types()] (e.g.
#'   `"university"`), or `NULL` (the default): the case study's loads.
#' @param electricity With `type`, the building's annual electricity per m2
#'   of floor (kWh/m2, e.g. a year's meter total over the floor area) to
#'   centre the loads on, in place of the type's benchmark; `NULL` (the
#'   default): the benchmark.
#' @return A data frame with 14 rows and columns `parameter`, `initial`,
#'   `min`, `max`, `unit`, `description`.
#' @family simulation
#' @export
#' @examples
#' bem_parameters()
#' bem_parameters(type = "office")[12:13, ]
#' bem_parameters(type = "laboratory", electricity = 450)[12:13, ]
bem_parameters <- function(type = NULL, electricity = NULL) {
  table <- data.frame(
    parameter = c("cooling_setpoint", "heating_setpoint", "fan_total_efficiency",
                  "fan_motor_efficiency", "dx_cooling_cop", "gas_burner_efficiency",
                  "baseboard_capacity", "wall_R_multiplier", "wall_density_multiplier",
                  "roof_R_multiplier", "roof_density_multiplier", "equipment_power_density",
                  "lighting_power_density", "infiltration_per_exterior_area"),
    initial = c(23.9, 18.3, 0.5, 0.9, 3, 0.95, 1500, 1, 1, 1, 1, 21.9, 14.6, 0.001524),
    min = c(21, 15, 0.1, 0.86, 1, 0.8, 1200, 0.9, 0.98, 0.9, 0.98, 3, 2, 0),
    max = c(25, 20.5, 0.9, 1.0, 6, 1.0, 1800, 1.1, 1.02, 1.1, 1.02, 30, 20, 0.001524),
    unit = c("C", "C", "-", "-", "-", "-", "W", "-", "-", "-", "-", "W/m2", "W/m2", "m3/s-m2"),
    description = c("cooling setpoint", "heating setpoint", "fan total efficiency",
                    "fan motor efficiency", "DX cooling coil COP", "gas burner efficiency",
                    "electric baseboard capacity", "exterior wall R-value multiplier",
                    "exterior wall density multiplier", "roof R-value multiplier",
                    "roof density multiplier", "electric equipment power density",
                    "lighting power density", "infiltration per exterior surface area")
  )
  if (!is.null(electricity)) {
    if (is.null(type)) {
      abort_bayesbem(c("{.arg electricity} needs a {.arg type}: the loads it centres are a type's.",
                       i = "E.g. {.code bem_parameters(type = \"university\", electricity = 300)}."),
                     "argument")
    }
    check_number(electricity, "argument", positive = TRUE)
  }
  if (is.null(type)) {
    return(table)
  }
  loads <- type_loads(type, electricity)
  at <- match(loads$parameter, table$parameter)
  table[at, c("initial", "min", "max")] <- loads[c("initial", "min", "max")]
  table
}

#' Fixed properties of the embedded building model
#'
#' Geometry, constructions, schedules and systems of a small single-storey
#' commercial building like the case study's (79 m2, occupied around the
#' clock, constant-volume fan, DX cooling, gas furnace, electric baseboard).
#' Every element can be changed by name.
#'
#' @param ... Named values replacing the defaults (see Value).
#' @return A list: `floor_area` (m2), `wall_area` (gross, m2),
#'   `window_fraction`, `roof_area` (m2), `u_wall`, `u_roof`, `u_window`,
#'   `u_floor` (W/m2K, before R-value multipliers), `floor_loss_factor`
#'   (share of the floor loss that goes to outdoor air), `shgc`,
#'   `frame_factor`, `kappa_wall`, `kappa_roof`, `kappa_internal` (areal heat
#'   capacities, J/m2K), `lighting_fraction`, `equipment_fraction` (mean
#'   share of the power densities in use), `occupant_gain` (W),
#'   `outdoor_air` (m3/s), `fan_flow` (m3/s), `fan_pressure` (Pa),
#'   `baseboard_share` (share of the heating need met by the baseboard, up
#'   to its capacity), `occupancy` (168 shares of full occupancy, hour by
#'   hour of the week from Monday 0:00, for [bem_hourly()]: by default 1 on
#'   weekdays from 7:00 to 19:00, 0 otherwise), `clock` (the time zone
#'   whose clock the occupancy follows, e.g. `"Europe/London"`, summer time
#'   included; `NULL`, the default: the weather file's standard time) and
#'   `holidays` (`Date`s, in that clock, whose hours follow Sunday's
#'   occupancy; `NULL`: none). `heating_schedule`: when the heating plant
#'   runs, 168 shares as `occupancy` (1: the heating set point held, 0:
#'   the plant off and the air held only above `heating_setback`, in C;
#'   between, the set point that share of the way from the setback), on
#'   the same clock; `NULL`, the default: around the clock, as the case
#'   study's. Most non-domestic heating runs on a timer, off at night: a
#'   gas meter's own winter profile shows its hours ([meter_heating_schedule()]).
#'   The monthly model uses the mean shares, and the set point's mean over
#'   the week. `cooling`: whether the building is cooled (`FALSE`: no DX coil,
#'   the air floats above the cooling set point, no cooling electricity;
#'   most of Europe's older offices and campuses).
#' @family simulation
#' @export
#' @examples
#' bem_building(floor_area = 100)
bem_building <- function(...) {
  defaults <- list(
    floor_area = 79, wall_area = 106.8, window_fraction = 0.15, roof_area = 79,
    u_wall = 0.5, u_roof = 0.2, u_window = 2.9, u_floor = 0.4, floor_loss_factor = 0.5,
    shgc = 0.6, frame_factor = 0.8,
    kappa_wall = 80e3, kappa_roof = 50e3, kappa_internal = 110e3,
    lighting_fraction = 0.6, equipment_fraction = 0.7, occupant_gain = 200,
    outdoor_air = 0.03, fan_flow = 0.45, fan_pressure = 500, baseboard_share = 0.15,
    occupancy = rep(c(rep(c(rep(0, 7), rep(1, 12), rep(0, 5)), 5), rep(0, 48))),
    clock = NULL, holidays = NULL, cooling = TRUE, heating_schedule = NULL, heating_setback = 12
  )
  changes <- list(...)
  unknown <- setdiff(names(changes), names(defaults))
  if (length(unknown) > 0L || is.null(names(changes)) && length(changes) > 0L) {
    abort_bayesbem(c("Unknown building propert{?y/ies} {.field {unknown}}.",
                     i = "Known properties: {.field {names(defaults)}}."),
                   "argument")
  }
  check_week_shares(changes$occupancy, "occupancy")
  check_week_shares(changes$heating_schedule, "heating_schedule")
  if (!is.null(changes$heating_setback)) {
    check_between(changes$heating_setback, -50, 30, arg = "heating_setback")
  }
  check_clock(changes$clock, changes$holidays)
  if (!is.null(changes$cooling)) check_bool(changes$cooling, arg = "cooling")
  # (modifyList() would drop a property set to NULL)
  out <- defaults
  out[names(changes)] <- changes
  out
}

#' The embedded building model of a building described by its facts
#'
#' A practitioner knows a building's floor area, its floors and its roof
#' area. `bem_building_facts()` scales the case study's building
#' ([bem_building()]) to them: a square footprint of `floor_area / floors`,
#' facades of `storey_height` per floor around it (the case study's 3 m:
#' its 106.8 m2 of wall around 79 m2), the roof given, the floor's loss
#' from the footprint alone, and the properties that grow with the floor
#' (occupants' gains, outdoor air, the fan's flow) in proportion to it;
#' constructions, shares and schedules stay the case study's unless given.
#' The loads of [bem_parameters()] are per m2 of floor and serve any size;
#' `bem_parameters(type =)` gives the loads of a type of use.
#'
#' With `type`, the occupancy is the type's opening hours
#' ([bem_building_types()]), unless `occupancy` is given: common hours, not
#' measured; [meter_occupancy()] estimates them from a meter's readings.
#' The lighting's mean share in use (`lighting_fraction`) follows the
#' opening hours (all of it while open, a tenth while closed).
#'
#' With `age`, the walls', roof's, floor's and windows' U-values are the
#' limits of the Building Regulations' edition in force that year
#' ([bem_envelope_standards()]), where it sets one; `u_wall` and the
#' others given in `...` take precedence.
#'
#' @param floor_area The floor area of all floors (m2).
#' @param floors The number of floors.
#' @param roof_area The roof's area (m2); by default the footprint.
#' @param storey_height The height of a floor (m).
#' @param type A building type of [bem_building_types()], or `NULL` (the
#'   default): the case study's schedule.
#' @param age The year the building was built to the regulations of (e.g.
#'   `1980`), from 1965, or `NULL` (the default): the case study's
#'   constructions.
#' @param ... Further properties of [bem_building()] (e.g. `occupancy`,
#'   `clock`, `window_fraction`, `u_wall`).
#' @return Building properties, as [bem_building()]'s.
#' @family simulation
#' @export
#' @examples
#' all.equal(bem_building_facts(79), bem_building())
#' bem_building_facts(6000, floors = 4, clock = "Europe/London")[c("wall_area", "roof_area")]
#' matrix(bem_building_facts(6000, type = "retail")$occupancy, 24)
bem_building_facts <- function(floor_area, floors = 1L, roof_area = floor_area / floors,
                               storey_height = 3, type = NULL, age = NULL, ...) {
  for (arg in c("floor_area", "roof_area", "storey_height")) check_number(get(arg), "argument", positive = TRUE, arg = arg)
  check_count(floors)
  case <- bem_building()
  footprint <- floor_area / floors
  ratio <- floor_area / case$floor_area
  facts <- list(floor_area = floor_area, roof_area = roof_area,
                wall_area = 4 * sqrt(footprint) * storey_height * floors,
                floor_loss_factor = case$floor_loss_factor * footprint / floor_area,
                occupant_gain = case$occupant_gain * ratio, outdoor_air = case$outdoor_air * ratio,
                fan_flow = case$fan_flow * ratio)
  if (!is.null(type)) {
    facts$occupancy <- type_occupancy(type)
    facts$lighting_fraction <- type_lighting_share(type)
  }
  if (!is.null(age)) facts <- utils::modifyList(facts, envelope_of_age(age))
  facts[names(list(...))] <- list(...)
  rlang::inject(bem_building(!!!facts))
}

# A schedule of bem_building(): 168 shares from 0 to 1 (or NULL).
check_week_shares <- function(x, field, call = rlang::caller_env()) {
  if (!is.null(x) && (!is.numeric(x) || length(x) != 168L || anyNA(x) || any(x < 0 | x > 1))) {
    abort_bayesbem(c("{.field {field}} must be 168 shares between 0 and 1, one per hour of the week from Monday 0:00.",
                     x = "It is {describe_value(x)} of length {length(x)}."),
                   "argument", call = call)
  }
}

# The heating set point each hour of the week (168 values, C): the
# parameter's where the plant runs, the building's setback where it is off.
heating_setpoints <- function(setpoint, building) {
  on <- building$heating_schedule
  if (is.null(on)) {
    return(rep(setpoint, 168L))
  }
  building$heating_setback + on * (setpoint - building$heating_setback)
}

check_clock <- function(clock, holidays, call = rlang::caller_env()) {
  if (!is.null(clock) && (!is.character(clock) || length(clock) != 1L ||
                          !clock %in% OlsonNames())) {
    abort_bayesbem(c("{.field clock} must name a time zone, not {describe_value(clock)}.",
                     i = "E.g. {.val Europe/London} or {.val America/Denver} (see {.fn OlsonNames})."),
                   "argument", call = call)
  }
  if (!is.null(holidays) && (!inherits(holidays, "Date") || anyNA(holidays))) {
    abort_bayesbem("{.field holidays} must be {.cls Date}s, not {describe_value(holidays)}.",
                   "argument", call = call)
  }
}

# The weekday (1 Monday to 7) and hour (0-23) whose schedule each hour of
# `weather` follows: on the building's clock (its summer time) when it has
# one, else the file's standard time; a holiday is a Sunday.
schedule_calendar <- function(weather, building, call = rlang::caller_env()) {
  if (is.null(building$clock) && is.null(building$holidays)) {
    return(list(weekday = weather$weekday, hour = weather$hour))
  }
  if (!inherits(weather$time, "POSIXct")) {
    abort_bayesbem("A building with a {.field clock} or {.field holidays} needs the hours' {.field time}, as {.code epw_weather(by = \"hour\")} gives.",
                   "argument", call = call)
  }
  zone <- building$clock %||% (attr(weather$time, "tzone") %||% "UTC")
  weekday <- as.integer(format(weather$time, "%u", tz = zone))
  day <- as.Date(format(weather$time, "%Y-%m-%d", tz = zone))
  weekday[day %in% building$holidays] <- 7L
  list(weekday = weekday, hour = as.integer(format(weather$time, "%H", tz = zone)))
}

# The hour of the week (1 = Monday 0:00 to 168) of schedule_calendar().
schedule_hours <- function(weather, building) {
  at <- schedule_calendar(weather, building)
  (at$weekday - 1L) * 24L + at$hour + 1L
}

#' Monthly energy use of the embedded building model (ISO 13790)
#'
#' The monthly quasi-steady-state method of ISO 13790 (ISO 52016-1) for one
#' thermal zone, with the systems of the case-study building. For each month
#' of `hours` hours at mean outdoor temperature `theta_e`:
#'
#' * heat transfer coefficients: transmission
#'   `H_tr = u_wall / wall_R_multiplier * A_wall + u_roof / roof_R_multiplier * A_roof
#'   + u_window * A_window + floor_loss_factor * u_floor * A_floor`, and
#'   ventilation `H_ve = 1206 * (infiltration_per_exterior_area * (A_wall + A_roof) + outdoor_air)`
#'   (W/K);
#' * losses at set point `theta`: `Q_ht = (H_tr + H_ve) * (theta - theta_e) * hours` (Wh);
#' * gains: internal `Q_int = (lighting_fraction * LPD + equipment_fraction * EPD) * A_floor * hours
#'   + occupant_gain * hours + P_fan * fan_motor_efficiency * hours`, and solar
#'   `Q_sol = I_vert * A_window * shgc * frame_factor * hours` with the mean
#'   irradiance on the facades `I_vert = 0.2 dni + 0.5 dhi + 0.1 ghi`;
#' * time constant `tau = C_m / (H_tr + H_ve) / 3600` (h) with
#'   `C_m = kappa_wall * wall_density_multiplier * A_wall + kappa_roof * roof_density_multiplier * A_roof
#'   + kappa_internal * A_floor`, and `a = 1 + tau / 15`;
#' * heating need `Q_H = Q_ht,H - eta_gn * Q_gn` with gain ratio
#'   `gamma = Q_gn / Q_ht,H` and utilisation `eta_gn = (1 - gamma^a) / (1 - gamma^(a + 1))`
#'   (`a / (a + 1)` at `gamma = 1`); zero when `Q_ht,H <= 0`;
#' * cooling need `Q_C = Q_gn - eta_ls * Q_ht,C` with loss ratio
#'   `lambda = Q_ht,C / Q_gn` and utilisation
#'   `eta_ls = (1 - lambda^-a) / (1 - lambda^-(a + 1))` (`a / (a + 1)` at
#'   `lambda = 1`, 1 when `lambda <= 0`); zero when negative.
#'
#' Electricity is lighting + equipment + fan (`P_fan = fan_flow * fan_pressure /
#' fan_total_efficiency`, running continuously) + DX cooling (`Q_C / dx_cooling_cop`)
#' + baseboard (`min(baseboard_share * Q_H, baseboard_capacity * hours)`); gas
#' is the rest of the heating need over `gas_burner_efficiency`.
#'
#' @param parameters A named list or one-row data frame with all 14
#'   parameters of [bem_parameters()] (physical units).
#' @param weather Monthly weather as from [epw_monthly()] (columns `hours`,
#'   `temp`, `dni`, `dhi`, `ghi`).
#' @param building Building properties from [bem_building()].
#' @return A data frame with one row per month: `electricity` and `gas`
#'   (kWh), and the needs `heating_need` and `cooling_need` (kWh).
#' @family simulation
#' @export
#' @examples
#' p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
#' w <- epw_monthly(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#' bem_monthly(p, w)
bem_monthly <- function(parameters, weather, building = bem_building()) {
  k <- bem_constants(parameters, building)
  p <- k$p
  b <- building
  hours <- weather$hours
  h <- k$h_tr + k$h_ve
  a <- 1 + k$c_m / h / 3600 / 15
  lights <- k$lights * hours
  equipment <- k$equipment * hours
  gains <- lights + equipment + k$occupants * hours + k$fan_heat * hours + k$solar(weather) * hours
  loss_heating <- h * (mean(heating_setpoints(p$heating_setpoint, b)) - weather$temp) * hours
  loss_cooling <- h * (p$cooling_setpoint - weather$temp) * hours
  heating <- ifelse(loss_heating > 0,
                    pmax(loss_heating - gain_utilisation(gains / loss_heating, a) * gains, 0), 0)
  cooling <- pmax(gains - loss_utilisation(loss_cooling / gains, a) * loss_cooling, 0)
  if (!isTRUE(b$cooling %||% TRUE)) cooling <- 0 * cooling
  bem_meters(k, heating, cooling, lights + equipment + k$p_fan * hours, hours)
}

# What the embedded models share (W, W/K, J/K; see ?bem_monthly): the
# transmission and ventilation conductances, the heat capacity, the mean
# power of lights, equipment, occupants and the fan (its heat to the air
# after the motor), and the facades' solar gain as a function of weather.
bem_constants <- function(parameters, b) {
  p <- as.list(parameters)
  a_window <- b$window_fraction * b$wall_area
  a_wall <- b$wall_area - a_window
  wall <- b$u_wall / p$wall_R_multiplier * a_wall
  roof <- b$u_roof / p$roof_R_multiplier * b$roof_area
  floor <- b$floor_loss_factor * b$u_floor * b$floor_area
  p_fan <- b$fan_flow * b$fan_pressure / p$fan_total_efficiency
  list(p = p, a_window = a_window, h_tr_op = wall + roof + floor, h_tr_w = b$u_window * a_window,
       h_tr = wall + roof + b$u_window * a_window + floor,
       h_ve = 1206 * (p$infiltration_per_exterior_area * (b$wall_area + b$roof_area) + b$outdoor_air),
       c_m = b$kappa_wall * p$wall_density_multiplier * b$wall_area +
         b$kappa_roof * p$roof_density_multiplier * b$roof_area + b$kappa_internal * b$floor_area,
       p_fan = p_fan, fan_heat = p_fan * p$fan_motor_efficiency,
       lights = b$lighting_fraction * p$lighting_power_density * b$floor_area,
       equipment = b$equipment_fraction * p$equipment_power_density * b$floor_area,
       occupants = b$occupant_gain, baseboard_share = b$baseboard_share,
       solar = function(weather) {
         (0.2 * weather$dni + 0.5 * weather$dhi + 0.1 * weather$ghi) * a_window * b$shgc * b$frame_factor
       })
}

# The meters from the heating and cooling needs (Wh per period of `hours`
# hours) and the other electric use: the baseboard meets its share of the
# heating need up to its capacity, gas the rest at the burner's efficiency,
# the DX coil the cooling need at its COP. kWh.
bem_meters <- function(k, heating, cooling, other_electricity, hours) {
  p <- k$p
  baseboard <- pmin(k$baseboard_share * heating, p$baseboard_capacity * hours)
  electricity <- other_electricity + cooling / p$dx_cooling_cop + baseboard
  gas <- (heating - baseboard) / p$gas_burner_efficiency
  data.frame(electricity = electricity / 1000, gas = gas / 1000,
             heating_need = heating / 1000, cooling_need = cooling / 1000)
}

# ISO 13790 gain utilisation factor for heating, gamma = gains / losses > 0.
gain_utilisation <- function(gamma, a) {
  ifelse(abs(gamma - 1) < 1e-9, a / (a + 1), (1 - gamma^a) / (1 - gamma^(a + 1)))
}

# ISO 13790 loss utilisation factor for cooling, lambda = losses / gains.
loss_utilisation <- function(lambda, a) {
  ifelse(lambda <= 0, 1,
         ifelse(abs(lambda - 1) < 1e-9, a / (a + 1),
                (1 - lambda^(-a)) / (1 - lambda^(-(a + 1)))))
}
