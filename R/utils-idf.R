# Reading, editing and writing EnergyPlus IDF files, and the parameter map
# that says which IDF fields a calibration parameter sets. An IDF is a list
# of objects, each a character vector: the class, then the fields.

# readLines() decompresses gzipped files itself, so `path` may be `.idf.gz`.
read_idf <- function(path) {
  text <- paste(sub("!.*$", "", readLines(path, warn = FALSE)), collapse = "\n")
  objects <- strsplit(text, ";", fixed = TRUE)[[1]]
  objects <- lapply(strsplit(objects, ",", fixed = TRUE), trimws)
  Filter(function(o) length(o) > 0L && nzchar(o[1]), objects)
}

write_idf <- function(model, path) {
  lines <- vapply(model, function(o) {
    paste0(o[1], ",\n  ", paste(o[-1], collapse = ",\n  "), ";\n")
  }, character(1))
  writeLines(lines, path)
}

check_idf_version <- function(model, version, path, call = rlang::caller_env()) {
  v <- Filter(function(o) tolower(o[1]) == "version", model)
  idf_version <- if (length(v) > 0L) sub("^([0-9]+\\.[0-9]+).*", "\\1", v[[1]][2]) else "unknown"
  if (!identical(idf_version, version)) {
    abort_bayesbem(c("{.path {basename(path)}} is an EnergyPlus {idf_version} model, but EnergyPlus is version {version}.",
                     i = "Convert the model with EnergyPlus's IDFVersionUpdater, or point {.arg eplus} to EnergyPlus {idf_version}."),
                   "eplus_version", call = call)
  }
}

# Field names of each requested class, in order, from the IDD.
idd_fields <- function(idd_path, classes) {
  idd <- readLines(idd_path, warn = FALSE)
  headers <- grep("^[A-Za-z][^ ,;]*[,;]\\s*$", idd)
  names(headers) <- tolower(sub("[,;]\\s*$", "", idd[headers]))
  lapply(stats::setNames(nm = unique(tolower(classes))), function(cls) {
    start <- headers[cls]
    if (is.na(start)) {
      return(NULL)
    }
    end <- c(headers[headers > start], length(idd) + 1L)[1] - 1L
    body <- idd[start:end]
    tolower(trimws(sub(".*\\\\field\\s+", "", grep("\\\\field\\s", body, value = TRUE))))
  })
}

#' The study's parameter map for the shipped EnergyPlus model
#'
#' The 14 uncertain parameters of the case study (see [bem_parameters()])
#' mapped onto the fields of the shipped EnergyPlus 25.2 model of the
#' building: one row per IDF field a parameter sets, with the parameter's
#' initial value and range. Setpoints set the first interval of the
#' weekday and weekend day schedules; R-value multipliers divide each layer's
#' conductivity; density multipliers multiply each layer's density. Edit a
#' copy to map parameters onto another model; see [eplus_simulator()].
#'
#' @return A data frame with columns `parameter`, `object_type`,
#'   `object_name`, `field`, `apply`, `initial`, `min` and `max`.
#' @family simulation
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

# Checks the map against the model and adds, for each row, the object's
# position in the model, the field's position in the object and the
# field's original value.
check_parameter_map <- function(map, model, idd_path, call = rlang::caller_env()) {
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
  fields <- idd_fields(idd_path, map$object_type)
  key <- vapply(model, function(o) tolower(paste(o[1], o[2], sep = "\r")), character(1))
  map$object <- match(tolower(paste(map$object_type, map$object_name, sep = "\r")), key)
  map$position <- mapply(function(cls, f) match(tolower(f), fields[[tolower(cls)]]) + 1L,
                         map$object_type, map$field, USE.NAMES = FALSE)
  unmatched <- is.na(map$object) | is.na(map$position)
  if (any(unmatched)) {
    where <- sprintf("%s %s: %s", map$object_type, map$object_name, map$field)[unmatched]
    abort_bayesbem(c("{.arg map} names IDF fields the model does not have:",
                     stats::setNames(where, rep("x", length(where))),
                     i = "Check the object types and names in the IDF, and the field names in {.file Energy+.idd}."),
                   "parameters", call = call)
  }
  map$original <- mapply(function(i, pos) suppressWarnings(as.numeric(model[[i]][pos])),
                         map$object, map$position)
  scaled <- map$apply != "value" & !is.finite(map$original)
  if (any(scaled)) {
    abort_bayesbem(c("Fields scaled by a multiplier must hold a number in the model.",
                     x = "Not: {.val {map$field[scaled]}} of {.val {map$object_name[scaled]}}."),
                   "parameters", call = call)
  }
  map
}

# The model with the fields of `map` set for one run's parameters.
set_idf_fields <- function(model, map, params) {
  for (i in which(map$parameter %in% names(params))) {
    value <- params[[map$parameter[i]]]
    value <- switch(map$apply[i], value = value, multiply = map$original[i] * value,
                    divide = map$original[i] / value)
    obj <- model[[map$object[i]]]
    length(obj) <- max(length(obj), map$position[i])
    obj[is.na(obj)] <- ""
    obj[map$position[i]] <- format(value, digits = 15)
    model[[map$object[i]]] <- obj
  }
  model
}
