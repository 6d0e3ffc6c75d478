#' Run an EnergyPlus model
#'
#' `eplus_run()` runs a model (see [eplus_model()]) on a weather file in a
#' folder of its own, under a time limit (`HVACTemplate:*`
#' objects were expanded when the model was read): `Output:SQLite` is
#' added when the model lacks it, and the fields of the model are checked by
#' EnergyPlus's converter beforehand (a field name EnergyPlus does not know
#' is an error, not silently dropped). `eplus_errors()` returns the
#' warnings, severe and fatal errors of a run's `eplusout.err`, as eplusr's
#' `$errors()` does.
#'
#' @param model A `bayesbem_eplus_model`.
#' @param weather Path of the EPW weather file (or `.epw.gz`).
#' @param dir Folder for the run's files; by default a new temporary folder.
#' @param timeout Time limit of the run in seconds (whole seconds, rounded
#'   up).
#' @param eplus Directory of EnergyPlus, see [eplus_path()].
#' @param run A `bayesbem_eplus_run` from `eplus_run()`.
#' @return `eplus_run()`: a `bayesbem_eplus_run`, a list with the run's
#'   `dir`, `ok` (whether EnergyPlus completed successfully), `sql` (path of
#'   its SQLite output) and `time` (seconds). A run that fails or hits the
#'   time limit is an error of class `bayesbem_error_eplus_run` quoting
#'   EnergyPlus's severe and fatal messages. `eplus_errors()`: a data frame
#'   with columns `level` (`"Warning"`, `"Severe"` or `"Fatal"`) and
#'   `message` (continuation lines joined).
#' @family EnergyPlus
#' @export
#' @examples
#' \donttest{
#' if (eplus_available()) {
#'   model <- eplus_model(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
#'   run <- eplus_run(model, system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
#'   table(eplus_errors(run)$level)
#'   eplus_output(run, "Electricity:Facility")
#' }
#' }
eplus_run <- function(model, weather, dir = NULL, timeout = 600, eplus = NULL) {
  check_eplus_model(model)
  check_file(weather, "weather")
  check_number(timeout, "argument", positive = TRUE)
  eplus <- eplus_path(eplus)
  check_model_fields(model, eplus)
  model <- weather_run_years(model, read_epw_hourly(weather))
  run_model(with_sqlite(model), weather, eplus, dir, timeout)
}

# A RunPeriod dated in another year than a file of actual weather
# (consecutive dates) cannot run on it: EnergyPlus then reports a year
# of the wrong length or weekdays of another calendar. Such periods take
# the weather's years, with a message; undated periods are left as the
# model has them (its start weekday).
weather_run_years <- function(model, hourly) {
  if (is.null(model$json$RunPeriod) || !actual_weather(record_dates(hourly))) {
    return(model)
  }
  years <- hourly$year[c(1, nrow(hourly))]
  dated <- vapply(model$json$RunPeriod, function(period) {
    !is.null(period$begin_year) && !identical(as.integer(c(period$begin_year, period$end_year %||% period$begin_year)),
                                               as.integer(years))
  }, logical(1))
  if (!any(dated)) {
    return(model)
  }
  cli::cli_inform(c(i = "The model's {.field RunPeriod} {.val {names(dated)[dated]}} {?is/are} dated {model$json$RunPeriod[[which(dated)[1]]]$begin_year}; run on the weather's years, {paste(unique(years), collapse = '-')}, with their weekdays."),
                  class = "bayesbem_message_run_period")
  model$json$RunPeriod[dated] <- lapply(model$json$RunPeriod[dated], function(period) {
    period$begin_year <- years[1]
    period$end_year <- years[2]
    period$day_of_week_for_start_day <- NULL
    period
  })
  model
}

#' @rdname eplus_run
#' @export
eplus_errors <- function(run) {
  check_eplus_run(run)
  read_err(file.path(run$dir, "eplusout.err"))
}

check_eplus_run <- function(run, call = rlang::caller_env()) {
  if (!inherits(run, "bayesbem_eplus_run")) {
    abort_bayesbem("{.arg run} must be a run from {.fn eplus_run}, not {describe_value(run)}.",
                   "argument", call = call)
  }
}

#' @export
print.bayesbem_eplus_run <- function(x, ...) {
  rlang::check_dots_empty()
  errors <- eplus_errors(x)
  cat_lines("{.cls bayesbem_eplus_run}: {if (x$ok) 'completed' else 'failed'} in {round(x$time, 1)} s, {.path {x$dir}}",
            "* {sum(errors$level == 'Warning')} warning{?s}, {sum(errors$level == 'Severe')} severe error{?s}")
  invisible(x)
}

# Runs `model` (already checked, with its outputs) and returns the run, or
# fails with EnergyPlus's messages.
run_model <- function(model, weather, eplus, dir, timeout, call = rlang::caller_env()) {
  dir <- dir %||% tempfile("eplus-run-")
  dir.create(dir, showWarnings = FALSE, recursive = TRUE)
  run <- leap_day_setup(model, plain_file(weather, dir), dir)
  input <- file.path(dir, "in.epJSON")
  write_epjson(run$model$json, input)
  args <- c("-w", run$weather, "-d", dir, input)
  result <- run_energyplus(eplus, args, dir, timeout)
  if (!result$ok) {
    abort_eplus_errors(result, "EnergyPlus ended with an error.",
                       i = "Check the model and the parameter values of this run.", call = call)
  }
  structure(list(dir = dir, ok = TRUE, sql = file.path(dir, "eplusout.sql"), time = result$time),
            class = "bayesbem_eplus_run")
}

# EnergyPlus simulates 29 February only when the weather file's header
# allows leap years (HOLIDAYS/DAYLIGHT SAVINGS, field 2) and the run period
# lies in a leap year; measured-weather files often hold the day under a
# header that says "No", and a run period without a year gets one from its
# start weekday. So that every day the file holds is simulated, a file
# whose records hold 29 February runs as a copy in `dir` whose header says
# "Yes", and each RunPeriod without years gets the records' years (EnergyPlus
# then takes the weekdays from the calendar, with a warning where the
# model's start weekday differs).
leap_day_setup <- function(model, weather, dir) {
  lines <- readLines(weather, warn = FALSE)
  records <- trimws(lines[-(1:8)])
  records <- records[nzchar(records)]
  if (!any(grepl("^[0-9]+\\s*,\\s*0?2\\s*,\\s*0?29\\s*,", records))) {
    return(list(model = model, weather = weather))
  }
  header <- strsplit(lines[5], ",", fixed = TRUE)[[1]]
  header[2] <- "Yes"
  lines[5] <- paste(header, collapse = ",")
  copy <- file.path(dir, paste0("leap-", basename(weather)))
  writeLines(lines, copy)
  years <- as.integer(sub(",.*", "", records[c(1, length(records))]))
  with_years <- function(period) {
    if (is.null(period$begin_year)) {
      period$begin_year <- years[1]
      period$end_year <- years[2]
    }
    period
  }
  if (!is.null(model$json$RunPeriod)) {
    model$json$RunPeriod <- lapply(model$json$RunPeriod, with_years)
  }
  list(model = model, weather = copy)
}

# Every field of the model known to EnergyPlus: the model goes through
# EnergyPlus's converter to IDF and back, which checks types and ranges
# (severe errors) and drops keys its schema does not have (found by
# comparing).
check_model_fields <- function(model, eplus, call = rlang::caller_env()) {
  tmp <- tempfile("eplus-check-")
  dir.create(tmp)
  on.exit(unlink(tmp, recursive = TRUE), add = TRUE)
  path <- file.path(tmp, "model.epJSON")
  write_epjson(model$json, path)
  idf <- convert_model(path, eplus, "idf", label = "the model", call = call)
  back <- read_epjson(convert_model(idf, eplus, "epJSON", label = "the model", call = call))
  lost <- unlist(lapply(names(model$json), function(class) {
    objects <- model$json[[class]]
    unlist(lapply(seq_along(objects), function(i) {
      # unnamed objects get their names back by position
      converted <- back[[class]][[names(objects)[i]]] %||% back[[class]][[i]]
      keys <- setdiff(object_keys(objects[[i]]), object_keys(converted))
      if (length(keys) > 0L) sprintf("%s %s: %s", class, names(objects)[i], keys)
    }))
  }))
  if (length(lost) > 0L) {
    abort_bayesbem(c("EnergyPlus does not know these fields:",
                     stats::setNames(utils::head(lost, 8), rep("x", min(length(lost), 8))),
                     i = "Use the field names of the IDD ({.file Energy+.idd}) for this version of EnergyPlus."),
                   "eplus_model", call = call)
  }
  invisible(model)
}

# The keys of an object, those of its arrays' items as "array/key".
object_keys <- function(object) {
  unlist(lapply(names(object), function(key) {
    value <- object[[key]]
    if (is_json_array(value)) {
      paste0(key, "/", unique(unlist(lapply(value, names))))
    } else {
      key
    }
  }))
}

# The model with SQLite output, which the results are read from.
with_sqlite <- function(model) {
  if (length(eplus_objects(model, "Output:SQLite")) == 0L) {
    model <- eplus_add(model, "Output:SQLite", option_type = "Simple")
  }
  model
}
