#' Envelope standards: the U-values a building of its age was built to
#'
#' What a building's age says about its envelope, for
#' [bem_building_facts()] (`age`): the maximum U-values (W/m2 K) of the
#' Building Regulations for England and Wales, edition by edition, from
#' their first limits (1965) to the 2002 edition, for exposed walls, roofs,
#' ground floors and (from 2002, metal-framed) windows. Where an edition
#' sets no limit for an element, the value is `NA` and the building keeps
#' the case study's ([bem_building()]).
#'
#' These are the limits a new building had to meet, not measured values:
#' a building is often better (or, through its workmanship, worse) than
#' its regulations, and the calibration's ranges (`wall_R_multiplier`,
#' `roof_R_multiplier` in [bem_parameters()]) are there to say so.
#'
#' @return A data frame with one row per edition: `edition` (its year),
#'   `u_wall`, `u_roof`, `u_floor`, `u_window`.
#' @references The Building Regulations (England and Wales), 1965, and
#'   their Approved Documents L (*Conservation of fuel and power*), 1976,
#'   1985, 1990, 1995 and 2002 editions, as summarised in
#'   "Energy efficiency in British housing: historic Building Regulations
#'   energy efficiency requirements".
#' @family simulation
#' @export
#' @examples
#' bem_envelope_standards()
#' bem_building_facts(5000, floors = 4, age = 1980)[c("u_wall", "u_roof", "u_floor")]
bem_envelope_standards <- function() {
  data.frame(edition = c(1965L, 1976L, 1985L, 1990L, 1995L, 2002L),
             u_wall = c(1.7, 1.0, 0.6, 0.45, 0.45, 0.35),
             u_roof = c(1.4, 0.6, 0.35, 0.25, 0.25, 0.25),
             u_floor = c(NA, 1.0, 0.6, 0.45, 0.45, 0.25),
             u_window = c(NA, NA, NA, NA, NA, 2.2))
}

# The U-values of bem_envelope_standards()' latest edition at or before
# the year `age`, the elements it limits only (a named list).
envelope_of_age <- function(age, call = rlang::caller_env()) {
  check_count(age, arg = "age", call = call)
  table <- bem_envelope_standards()
  if (age < min(table$edition)) {
    abort_bayesbem(c("The Building Regulations set no U-values before {min(table$edition)}; {.arg age} is {age}.",
                     i = "Give the constructions' U-values instead ({.field u_wall}, {.field u_roof}, {.field u_floor}, {.field u_window}), e.g. from a survey."),
                   "argument", call = call)
  }
  row <- table[max(which(table$edition <= age)), c("u_wall", "u_roof", "u_floor", "u_window")]
  as.list(row[, !is.na(unlist(row)), drop = FALSE])
}
