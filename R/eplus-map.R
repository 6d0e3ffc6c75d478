#' The study's parameter map for the shipped EnergyPlus model
#'
#' The 14 uncertain parameters of the case study (see [bem_parameters()])
#' mapped onto the fields of the shipped EnergyPlus 25.2 model of the
#' building: one row per field a parameter sets, with the parameter's
#' initial value and range. Setpoints set the first interval of the
#' weekday and weekend day schedules; R-value multipliers divide each layer's
#' conductivity; density multipliers multiply each layer's density. Edit a
#' copy to map parameters onto another model; see [eplus_simulator()].
#'
#' @return A data frame with columns `parameter`, `object_type`,
#'   `object_name`, `field`, `apply`, `initial`, `min` and `max`.
#' @family EnergyPlus
#' @export
#' @examples
#' head(eplus_parameter_map())
eplus_parameter_map <- function() {
  utils::read.csv(system.file("extdata", "seb_eplus_map.csv", package = "bayesbem"),
                  stringsAsFactors = FALSE)
}

# One parameter-table row per mapped parameter.
map_parameters <- function(map) {
  first <- map[!duplicated(map$parameter), c("parameter", "initial", "min", "max")]
  check_parameter_table(`rownames<-`(first, NULL), "map")
}

# Fields that only act under a calculation method (EnergyPlus 25.2 IDD): the
# load classes size their load by one of several fields, chosen by the
# method field; a value in another field is ignored by EnergyPlus.
calculation_methods <- function() {
  equipment <- function(per_area, per_person) {
    list(method = "design_level_calculation_method",
         fields = c(design_level = "EquipmentLevel", stats::setNames("Watts/Area", per_area),
                    stats::setNames("Watts/Person", per_person)))
  }
  flow <- function(per) {
    list(method = "design_flow_rate_calculation_method",
         fields = c(design_flow_rate = "Flow/Zone", flow_rate_per_floor_area = "Flow/Area",
                    per, air_changes_per_hour = "AirChanges/Hour"))
  }
  list(
    Lights = list(method = "design_level_calculation_method",
                  fields = c(lighting_level = "LightingLevel", watts_per_floor_area = "Watts/Area",
                             watts_per_person = "Watts/Person")),
    ElectricEquipment = equipment("watts_per_floor_area", "watts_per_person"),
    GasEquipment = equipment("power_per_floor_area", "power_per_person"),
    HotWaterEquipment = equipment("power_per_floor_area", "power_per_person"),
    SteamEquipment = equipment("power_per_floor_area", "power_per_person"),
    OtherEquipment = equipment("power_per_floor_area", "power_per_person"),
    People = list(method = "number_of_people_calculation_method",
                  fields = c(number_of_people = "People", people_per_floor_area = "People/Area",
                             floor_area_per_person = "Area/Person")),
    `ZoneInfiltration:DesignFlowRate` =
      flow(c(flow_rate_per_exterior_surface_area = "Flow/ExteriorArea")),
    `ZoneVentilation:DesignFlowRate` = flow(c(flow_rate_per_person = "Flow/Person"))
  )
}

# Checks the map against the model: known apply rules, objects that exist,
# numbers where a field is scaled, and fields that act under the object's
# calculation method. A field set by value under another method is set
# together with its method (the row gets `method_field`/`method_value`); a
# scaled one is refused, since its original value does not act.
check_parameter_map <- function(map, model, call = rlang::caller_env()) {
  needed <- c("parameter", "object_type", "object_name", "field", "apply", "initial", "min", "max")
  if (!is.data.frame(map) || !all(needed %in% names(map))) {
    abort_bayesbem(c("{.arg map} must be a data frame with columns {.field {needed}}.",
                     i = "Start from {.fn eplus_parameter_map}."),
                   "parameters", call = call)
  }
  bad_apply <- setdiff(map$apply, c("value", "multiply", "divide"))
  if (length(bad_apply) > 0L) {
    abort_bayesbem(c("{.field apply} must be {.val value}, {.val multiply} or {.val divide}.",
                     x = "{.arg map} has {.val {bad_apply}}."),
                   "parameters", call = call)
  }
  map <- expand_map_rows(map, model, call)
  missing <- !mapply(function(class, name) name %in% eplus_objects(model, class),
                     map$object_type, map$object_name)
  if (any(missing)) {
    where <- unique(sprintf("%s %s", map$object_type, map$object_name)[missing])
    abort_bayesbem(c("{.arg map} names objects the model does not have:",
                     stats::setNames(where, rep("x", length(where))),
                     i = "Check the object types and names against {.fn eplus_objects}."),
                   "parameters", call = call)
  }
  map$original <- vapply(seq_len(nrow(map)), function(i) {
    value <- eplus_get(model, map$object_type[i], map$object_name[i], map$field[i])
    if (is.numeric(value)) value else NA_real_
  }, numeric(1))
  scaled <- map$apply != "value" & !is.finite(map$original)
  if (any(scaled)) {
    abort_bayesbem(c("Fields scaled by a multiplier must hold a number in the model.",
                     x = "Not: {.val {map$field[scaled]}} of {.val {map$object_name[scaled]}}."),
                   "parameters", call = call)
  }
  method_rows(map, model, call)
}

# Rows whose object_name holds a wildcard ("*" for every object of the
# class, or a glob such as "Office*") become one row per object it matches,
# said in a message; a wildcard that matches nothing is an error.
expand_map_rows <- function(map, model, call) {
  wild <- grepl("[*?]", map$object_name)
  if (!any(wild)) {
    return(map)
  }
  rows <- lapply(seq_len(nrow(map)), function(i) {
    if (!wild[i]) {
      return(map[i, , drop = FALSE])
    }
    names <- eplus_objects(model, map$object_type[i])
    matched <- names[grepl(utils::glob2rx(map$object_name[i]), names)]
    if (length(matched) == 0L) {
      abort_bayesbem(c("{.arg map} row {i} ({.field {map$parameter[i]}}): {.val {map$object_name[i]}} matches no {.field {map$object_type[i]}} object.",
                       i = "Its objects are {.val {names}}."),
                     "parameters", call = call)
    }
    cli::cli_inform(c(i = "{.field {map$parameter[i]}}: {.field {map$object_type[i]}} {.val {map$object_name[i]}} matched {length(matched)} object{?s}: {.val {matched}}."),
                    class = "bayesbem_message_map_rows")
    out <- map[rep(i, length(matched)), , drop = FALSE]
    out$object_name <- matched
    out
  })
  out <- do.call(rbind, rows)
  rownames(out) <- NULL
  out
}

method_rows <- function(map, model, call) {
  methods <- calculation_methods()
  map$method_field <- NA_character_
  map$method_value <- NA_character_
  for (i in seq_len(nrow(map))) {
    rule <- methods[[map$object_type[i]]]
    key <- field_key(map$field[i])
    if (is.null(rule) || !key %in% names(rule$fields)) next
    needed <- rule$fields[[key]]
    current <- eplus_get(model, map$object_type[i], map$object_name[i], rule$method)
    if (identical(current, needed)) next
    if (map$apply[i] != "value") {
      abort_bayesbem(c("{.field {map$field[i]}} of {.field {map$object_type[i]}} {.val {map$object_name[i]}} does not act: its {.field {rule$method}} is {.val {current}}.",
                       i = "Map the field of that method, or use {.code apply = \"value\"} so that the method is set to {.val {needed}} with it."),
                     "parameters", call = call)
    }
    cli::cli_inform(c(i = "{.field {map$object_type[i]}} {.val {map$object_name[i]}}: {.field {rule$method}} is set to {.val {needed}} so that {.field {map$field[i]}} acts."))
    map$method_field[i] <- rule$method
    map$method_value[i] <- needed
  }
  map
}

# The model with the fields of `map` set for one run's parameters, then the
# measures applied (each a function(model, value) of its parameter).
apply_parameters <- function(model, map, measures, params) {
  for (i in which(map$parameter %in% names(params))) {
    value <- params[[map$parameter[i]]]
    value <- switch(map$apply[i], value = value, multiply = map$original[i] * value,
                    divide = map$original[i] / value)
    fields <- stats::setNames(list(value), map$field[i])
    if (!is.na(map$method_field[i])) fields[[map$method_field[i]]] <- map$method_value[i]
    model <- do.call(eplus_set, c(list(model, map$object_type[i], map$object_name[i]), fields))
  }
  for (parameter in intersect(names(measures), names(params))) {
    model <- measures[[parameter]](model, params[[parameter]])
    if (!inherits(model, "bayesbem_eplus_model")) {
      abort_bayesbem(c("The measure of {.field {parameter}} must return the model.",
                       x = "It returned {describe_value(model)}."),
                     "parameters")
    }
  }
  model
}

check_measures <- function(measures, parameters, call = rlang::caller_env()) {
  ok <- is.list(measures) && (length(measures) == 0L ||
                                (!is.null(names(measures)) && all(nzchar(names(measures))) &&
                                   all(vapply(measures, is.function, logical(1)))))
  if (!ok) {
    abort_bayesbem(c("{.arg measures} must be a named list of functions {.code function(model, value)}.",
                     i = "Name each after the parameter it sets."),
                   "parameters", call = call)
  }
  unknown <- setdiff(names(measures), parameters$parameter)
  if (length(unknown) > 0L) {
    abort_bayesbem(c("{.arg measures} sets {.field {unknown}}, not in {.arg parameters}.",
                     i = "Add {.field {unknown}} to {.arg parameters} with an initial value and a range."),
                   "parameters", call = call)
  }
}
