#' Building types: benchmarks and lighting allowances by use
#'
#' What a practitioner's "type of use" says about a building, for
#' [bem_parameters()] (the loads' initial values and ranges) and
#' [bem_building_facts()] (the opening hours):
#'
#' * `electricity`, `fossil`: the typical annual electricity and fossil-fuel
#'   (heating) use per m2 of floor of the type's category in CIBSE TM46:2008,
#'   *Energy benchmarks*, Table 1 (the benchmarks of the UK's Display Energy
#'   Certificates), in kWh/m2 a year;
#' * `lighting`: the lighting power allowance of the building-area method of
#'   ANSI/ASHRAE/IESNA Standard 90.1-2004, Table 9.5.1 (W/ft2 converted at
#'   10.764 ft2/m2; a laboratory from the space-by-space method, Table 9.6.1),
#'   in W/m2;
#' * `open`, `close`: the hours a weekday's occupancy starts and ends, and
#'   `saturday`, `sunday`: whether the building opens those days (same hours).
#'   These are common opening hours, not from the tables above: where meter
#'   readings exist, [meter_occupancy()] estimates the schedule from them.
#'   The lighting is taken to be in use while open and a tenth of it while
#'   closed.
#'
#' @return A data frame with one row per type: `type`, `tm46_category`,
#'   `electricity`, `fossil`, `lighting`, `open`, `close`, `saturday`,
#'   `sunday`.
#' @references CIBSE (2008). *TM46: Energy benchmarks*. The Chartered
#'   Institution of Building Services Engineers, London.
#'
#'   ASHRAE (2004). *ANSI/ASHRAE/IESNA Standard 90.1-2004: Energy standard
#'   for buildings except low-rise residential buildings*. Atlanta.
#' @family simulation
#' @export
#' @examples
#' bem_building_types()
bem_building_types <- function() {
  w_per_ft2 <- c(office = 1.0, school = 1.2, university = 1.2, laboratory = 1.4, retail = 1.5,
                 hotel = 1.0, hospital = 1.2)
  data.frame(
    type = names(w_per_ft2),
    tm46_category = c("General office", "Schools and seasonal public buildings",
                      "University campus", "Laboratory or operating theatre", "General retail",
                      "Hotel", "Hospital (clinical and research)"),
    electricity = c(95, 40, 80, 160, 165, 105, 90),
    fossil = c(120, 150, 240, 160, 0, 330, 420),
    lighting = round(unname(w_per_ft2) * 10.764, 1),
    open = c(8, 8, 8, 8, 9, 0, 0), close = c(18, 16, 18, 19, 18, 24, 24),
    saturday = c(FALSE, FALSE, FALSE, FALSE, TRUE, TRUE, TRUE),
    sunday = c(FALSE, FALSE, FALSE, FALSE, FALSE, TRUE, TRUE)
  )
}

# The row of bem_building_types() named `type`.
building_type <- function(type, call = rlang::caller_env()) {
  types <- bem_building_types()
  types[types$type == match_choice(type, types$type, "type", call = call), ]
}

# The loads of a building type (bem_parameters(type =)), so that at their
# initial values the embedded model uses `electricity` (kWh/m2 a year; by
# default the type's typical TM46 electricity): lighting at the type's
# 90.1-2004 allowance, in use its share type_lighting_share() of the hours,
# and equipment (the case study's mean share in use, 0.7) the rest, at
# least a quarter of it. Ranges: the lighting from half the allowance (an
# LED refit), or half the mean power where that is lower (lights that
# share a low meter's base load cannot draw more than the meter), to one
# and a half times the allowance (older lamps); the equipment from a
# tenth to one and a half times that electricity's whole mean power in
# use, so that the prior spans meters well below and above it.
type_loads <- function(type, electricity = NULL, call = rlang::caller_env()) {
  row <- building_type(type, call = call)
  power <- (electricity %||% row$electricity) / 8.76
  equipment <- max(power - type_lighting_share(type) * row$lighting, 0.25 * power) / 0.7
  data.frame(parameter = c("equipment_power_density", "lighting_power_density"),
             initial = c(equipment, row$lighting),
             min = c(0.1 * power / 0.7, 0.5 * min(row$lighting, power)),
             max = 1.5 * c(power / 0.7, row$lighting))
}

# The type's weekly occupancy: 1 in its opening hours, 0 otherwise (168
# hours from Monday 0:00).
type_occupancy <- function(type, call = rlang::caller_env()) {
  row <- building_type(type, call = call)
  day <- as.numeric(seq(0, 23) >= row$open & seq(0, 23) < row$close)
  c(rep(day, 5), day * row$saturday, day * row$sunday)
}

# The mean share of the lighting in use (bem_building()'s
# `lighting_fraction`): all of it while open, a tenth while closed
# (cleaning, circulation, security).
type_lighting_share <- function(type, call = rlang::caller_env()) {
  open <- mean(type_occupancy(type, call = call))
  open + 0.1 * (1 - open)
}
