#' EnergyPlus models
#'
#' `eplus_model()` reads an EnergyPlus model into R: an IDF is converted to
#' EnergyPlus's own JSON format (epJSON) by the installed EnergyPlus
#' (`energyplus --convert-only`), an epJSON file is read as it is. Objects
#' are then addressed by class and name and fields by name, as in eplusr:
#' `eplus_get()` reads a field, `eplus_set()` sets fields, `eplus_add()` adds
#' an object, `eplus_del()` deletes one, `eplus_objects()` lists the objects of a class and
#' `eplus_save()` writes the model (epJSON, or IDF when the path ends in
#' `.idf`).
#'
#' Field names may be given as in the IDD or the IDF's comments
#' (`"Watts per Floor Area"`) or as epJSON keys (`"watts_per_floor_area"`).
#' A field of an extensible group takes its number at the end:
#' `"Value Until Time 2"` is the second interval of a `Schedule:Day:Interval`,
#' `"Field 4"` the fourth line of a `Schedule:Compact`.
#'
#' `HVACTemplate:*` objects of an IDF are expanded into the objects they
#' stand for by EnergyPlus's ExpandObjects when the model is read (as
#' `energyplus -x` does before a run), so parameters map onto the expanded
#' objects.
#'
#' The model's version must be the installed EnergyPlus's: a model of another
#' version is a classed error (`bayesbem_error_eplus_version`) naming both.
#' File names in the model (`Schedule:File`, window data files) that are
#' relative are resolved from the model's own folder when it is read, so the
#' model runs from anywhere. Field values are checked by EnergyPlus itself
#' when the model is run or turned into a simulator. Each conversion is kept
#' for the R session under the file's contents, so a model read again, or a
#' simulator made again from the same model, does not wait on EnergyPlus.
#'
#' @param path Path of an `.idf` or `.epJSON` file (or `.idf.gz`).
#' @param eplus Directory of EnergyPlus, see [eplus_path()].
#' @param model A `bayesbem_eplus_model`.
#' @param class An object class, e.g. `"Lights"`.
#' @param name The object's name. Unnamed objects (e.g. `Output:SQLite`)
#'   have names such as `"Output:SQLite 1"`; see `eplus_objects()`.
#' @param field A field name.
#' @param ... For `eplus_set()` and `eplus_add()`, fields as `name = value`
#'   pairs (names as in `field`, e.g. `` `Watts per Floor Area` = 10 `` or
#'   `watts_per_floor_area = 10`).
#' @return `eplus_model()`, `eplus_set()`, `eplus_add()`, `eplus_del()`: a
#'   `bayesbem_eplus_model`. `eplus_get()`: the field's value (`NULL` when
#'   the field is blank). `eplus_objects()`: the names of the class's
#'   objects. `eplus_save()`: the path, invisibly.
#' @family EnergyPlus
#' @export
#' @examples
#' \donttest{
#' if (eplus_available()) {
#'   model <- eplus_model(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
#'   model
#'   eplus_get(model, "Lights", "AllLights", "Watts per Floor Area")
#'   model <- eplus_set(model, "Lights", "AllLights", `Watts per Floor Area` = 10)
#'   eplus_objects(model, "Output:Meter")
#' }
#' }
eplus_model <- function(path, eplus = NULL) {
  check_file(path, "path")
  dir <- eplus_path(eplus)
  version <- eplus_version(dir)
  epjson <- grepl("\\.epjson$", path, ignore.case = TRUE)
  model_version <- if (epjson) epjson_version(jsonlite::read_json(path)) else idf_version(path)
  check_model_version(model_version, version, path)
  if (!epjson && has_templates(path)) path_read <- expand_objects(path, dir) else path_read <- path
  json <- if (epjson) read_epjson(path) else read_epjson(convert_model(path_read, dir, "epJSON"))
  if (any(startsWith(names(json), "HVACTemplate:"))) {
    abort_bayesbem(c("{.file {basename(path)}} has {.field HVACTemplate} objects, which only EnergyPlus's ExpandObjects turns into a model, and it reads IDF files only.",
                     i = "Read the model's IDF instead."),
                   "eplus_model")
  }
  model <- structure(list(json = json, version = version, source = normalizePath(path)),
                     class = "bayesbem_eplus_model")
  resolve_files(model, dirname(normalizePath(path)))
}

#' @rdname eplus_model
#' @export
eplus_get <- function(model, class, name, field) {
  check_eplus_model(model)
  object <- find_object(model, class, name)
  slot <- field_slot(object, field, class, name)
  if (is.null(slot$index)) object[[slot$key]] else object[[slot$array]][[slot$index]][[slot$key]]
}

#' @rdname eplus_model
#' @export
eplus_set <- function(model, class, name, ...) {
  check_eplus_model(model)
  fields <- named_fields(...)
  object <- find_object(model, class, name)
  for (field in names(fields)) {
    slot <- field_slot(object, field, class, name)
    if (is.null(slot$index)) {
      object[[slot$key]] <- fields[[field]]
    } else {
      object[[slot$array]][[slot$index]][[slot$key]] <- fields[[field]]
    }
  }
  model$json[[class]][[name]] <- object
  model
}

#' @rdname eplus_model
#' @export
eplus_add <- function(model, class, name = NULL, ...) {
  check_eplus_model(model)
  fields <- named_fields(...)
  names(fields) <- field_key(names(fields))
  if (startsWith(class, "HVACTemplate:")) {
    abort_bayesbem(c("{.field {class}} objects are expanded when a model is read, not added to it.",
                     i = "Add the object to the IDF, then read it with {.fn eplus_model}."),
                   "eplus_model")
  }
  existing <- names(model$json[[class]])
  name <- name %||% paste(class, length(existing) + 1L)
  if (name %in% existing) {
    abort_bayesbem("The model already has a {.field {class}} named {.val {name}}.", "eplus_model")
  }
  model$json[[class]][[name]] <- as_json_object(fields)
  model
}

#' @rdname eplus_model
#' @export
eplus_del <- function(model, class, name) {
  check_eplus_model(model)
  find_object(model, class, name)
  model$json[[class]][[name]] <- NULL
  if (length(model$json[[class]]) == 0L) model$json[[class]] <- NULL
  model
}

#' @rdname eplus_model
#' @export
eplus_objects <- function(model, class) {
  check_eplus_model(model)
  names(model$json[[class]]) %||% character()
}

#' @rdname eplus_model
#' @export
eplus_save <- function(model, path, eplus = NULL) {
  check_eplus_model(model)
  if (grepl("\\.idf$", path, ignore.case = TRUE)) {
    tmp <- tempfile(fileext = ".epJSON")
    on.exit(unlink(tmp), add = TRUE)
    write_epjson(model$json, tmp)
    file.copy(convert_model(tmp, eplus_path(eplus), "idf"), path, overwrite = TRUE)
  } else {
    write_epjson(model$json, path)
  }
  invisible(path)
}

#' @export
print.bayesbem_eplus_model <- function(x, ...) {
  rlang::check_dots_empty()
  n <- vapply(x$json, length, integer(1))
  cat_lines("{.cls bayesbem_eplus_model}: EnergyPlus {x$version}, from {.file {basename(x$source)}}",
            "* {sum(n)} object{?s} in {length(n)} class{?es}")
  invisible(x)
}

check_eplus_model <- function(model, arg = rlang::caller_arg(model), call = rlang::caller_env()) {
  if (!inherits(model, "bayesbem_eplus_model")) {
    abort_bayesbem(c("{.arg {arg}} must be an EnergyPlus model, not {describe_value(model)}.",
                     i = "Read one with {.fn eplus_model}."),
                   "argument", call = call)
  }
}

# The epJSON key of a field name: lower case, every run of other characters
# than letters and digits an underscore (as EnergyPlus names the keys, so a
# key given as such is unchanged).
field_key <- function(field) {
  gsub("[^a-z0-9]+", "_", tolower(field))
}

# Where a field lives in an object: a key of the object, or the key of an
# item of one of its extensible arrays ("Value Until Time 2": the
# `value_until_time` of the second item of the array whose items have it).
field_slot <- function(object, field, class, name, call = rlang::caller_env()) {
  key <- field_key(field)
  number <- regmatches(field, regexpr("[0-9]+$", field))
  arrays <- names(object)[vapply(object, is_json_array, logical(1))]
  if (length(number) == 0L || key %in% names(object) || length(arrays) == 0L) {
    return(list(key = key, array = NULL, index = NULL))
  }
  base <- sub("_?[0-9]+$", "", key)
  index <- as.integer(number)
  for (array in arrays) {
    items <- object[[array]]
    if (any(vapply(items, function(item) base %in% names(item), logical(1)))) {
      if (index < 1L || index > length(items)) {
        abort_bayesbem(c("{.field {class}} {.val {name}} has {length(items)} {.field {base}} entr{?y/ies}, not {index}.",
                         i = "Add the entry to the model first."),
                       "eplus_model", call = call)
      }
      return(list(key = base, array = array, index = index))
    }
  }
  list(key = key, array = NULL, index = NULL)
}

find_object <- function(model, class, name, call = rlang::caller_env()) {
  objects <- model$json[[class]]
  if (is.null(objects)) {
    abort_bayesbem(c("The model has no object of class {.field {class}}.",
                     i = "Class names are as in the IDD, e.g. {.val Lights}; see {.code names(model$json)}."),
                   "eplus_model", call = call)
  }
  if (!name %in% names(objects)) {
    abort_bayesbem(c("The model has no {.field {class}} named {.val {name}}.",
                     i = "Its {.field {class}} objects: {.val {utils::head(names(objects), 10)}}."),
                   "eplus_model", call = call)
  }
  objects[[name]]
}

named_fields <- function(..., call = rlang::caller_env()) {
  fields <- list(...)
  if (length(fields) > 0L && (is.null(names(fields)) || any(!nzchar(names(fields))))) {
    abort_bayesbem("Every field must be given as {.code name = value}.", "argument", call = call)
  }
  fields
}

# EnergyPlus's converter, `energyplus --convert-only`, turning `path` into the
# other format (`to`: "epJSON" or "idf") in a temporary folder.
convert_model <- function(path, dir, to, label = "{.file {basename(path)}}",
                          call = rlang::caller_env()) {
  label <- cli::format_inline(label)
  key <- conversion_key(path, dir, to)
  kept <- the_conversions[[key]]
  if (!is.null(kept) && file.exists(kept)) {
    return(kept)
  }
  out <- tempfile("eplus-convert-")
  dir.create(out)
  input <- plain_file(path, out)
  result <- run_energyplus(dir, c("--convert-only", "-d", out, input), out, timeout = 120)
  converted <- file.path(out, paste0(tools::file_path_sans_ext(basename(input)), ".", to))
  if (!result$ok || !file.exists(converted)) {
    abort_eplus_errors(result, "EnergyPlus rejected {label}.", call = call)
  }
  the_conversions[[key]] <- converted
  converted
}

# A conversion depends only on the file's contents (a `.gz` file's
# compressed ones: the lookup decompresses nothing), the format asked for
# and the EnergyPlus that converts, and each costs EnergyPlus's start-up:
# making a simulator converts its model at both ends of the ranges, and the
# same model is made into several simulators. The session keeps each
# converted file under that key (failures are not kept).
the_conversions <- new.env(parent = emptyenv())

conversion_key <- function(path, dir, to) {
  exe <- normalizePath(eplus_exe(dir))
  paste(unname(tools::md5sum(path)), to, exe, format(as.numeric(file.mtime(exe)), digits = 15),
        sep = "|")
}

# Whether an IDF has HVACTemplate objects (comments left out).
has_templates <- function(path) {
  any(grepl("^\\s*HVACTemplate:", sub("!.*$", "", readLines(path, warn = FALSE)), ignore.case = TRUE))
}

# EnergyPlus's ExpandObjects on an IDF: it reads `in.idf` and `Energy+.idd`
# in its working folder and writes `expanded.idf` there.
expand_objects <- function(path, dir, call = rlang::caller_env()) {
  out <- tempfile("eplus-expand-")
  dir.create(out)
  writeLines(readLines(path, warn = FALSE), file.path(out, "in.idf"))
  file.copy(file.path(dir, "Energy+.idd"), out)
  exe <- file.path(dir, if (.Platform$OS.type == "windows") "ExpandObjects.exe" else "ExpandObjects")
  result <- run_program(exe, character(), out, timeout = 120)
  expanded <- file.path(out, "expanded.idf")
  if (result$status != 0L || !file.exists(expanded)) {
    abort_bayesbem(c("EnergyPlus's ExpandObjects could not expand the {.field HVACTemplate} objects of {.file {basename(path)}}.",
                     x = "{utils::tail(result$output, 2)}"),
                   "eplus_model", call = call)
  }
  expanded
}

# The version of an IDF, read from its Version object without parsing the
# rest ("8.7" from "Version,8.7;").
idf_version <- function(path) {
  text <- paste(sub("!.*$", "", readLines(path, warn = FALSE)), collapse = " ")
  v <- regmatches(text, regexpr("(?i)\\bversion\\s*,\\s*[0-9]+\\.[0-9]+", text, perl = TRUE))
  if (length(v) == 0L) "unknown" else sub(".*,\\s*", "", v)
}

epjson_version <- function(json) {
  v <- json[["Version"]][[1]][["version_identifier"]]
  if (is.null(v)) "unknown" else sub("^([0-9]+\\.[0-9]+).*", "\\1", v)
}

check_model_version <- function(model_version, version, path, call = rlang::caller_env()) {
  if (!identical(model_version, version)) {
    abort_bayesbem(c("{.file {basename(path)}} is an EnergyPlus {model_version} model, but the installed EnergyPlus is version {version}.",
                     i = "Transition the model to {version} with EnergyPlus's IDFVersionUpdater (or eplusr's {.fn transition}), or point {.arg eplus} to EnergyPlus {model_version}."),
                   "eplus_version", call = call)
  }
}

# jsonlite reads `{}` as an unnamed empty list, which it would write as `[]`:
# empty lists are objects in epJSON (its arrays always hold items).
read_epjson <- function(path) {
  fix <- function(x) {
    if (!is.list(x)) return(x)
    if (length(x) == 0L) return(as_json_object(x))
    x[] <- lapply(x, fix)
    x
  }
  fix(jsonlite::read_json(path, simplifyVector = FALSE))
}

write_epjson <- function(json, path) {
  jsonlite::write_json(json, path, auto_unbox = TRUE, digits = NA, pretty = TRUE)
}

as_json_object <- function(x) {
  if (length(x) == 0L) structure(list(), names = character()) else x
}

is_json_array <- function(x) {
  is.list(x) && is.null(names(x)) && length(x) > 0L
}

# Relative file names (fields called `file_name`, as in Schedule:File and
# Construction:WindowDataFile) made absolute from the model's folder when
# the file is there.
resolve_files <- function(model, folder) {
  for (class in names(model$json)) {
    for (name in names(model$json[[class]])) {
      file <- model$json[[class]][[name]][["file_name"]]
      if (is.character(file) && !grepl("^(/|[A-Za-z]:)", file) &&
          file.exists(file.path(folder, file))) {
        model$json[[class]][[name]][["file_name"]] <- normalizePath(file.path(folder, file))
      }
    }
  }
  model
}
