#' EnergyPlus as a simulator
#'
#' Wraps an EnergyPlus model as a simulator: each run copies the IDF, sets
#' the fields the parameter map names, runs EnergyPlus on the weather file,
#' and returns a monthly meter in kWh (one value per month of the run
#' period), with the observable inputs `temp`, `rh` and `solar` of
#' [epw_monthly()] for the same weather, as in [seb_field].
#'
#' The map ([eplus_parameter_map()]) has one row per IDF field a parameter
#' sets: `parameter`, `object_type`, `object_name`, `field` (the field's name
#' in the IDD, any case) and `apply`: `"value"` sets the field to the
#' parameter's value, `"multiply"` to the original value times it (e.g. a
#' density multiplier), `"divide"` to the original value divided by it (an
#' R-value multiplier acting on conductivity). Field positions are looked up
#' in the `Energy+.idd` of the EnergyPlus installation, so the IDF's
#' comments do not matter.
#'
#' EnergyPlus is found by [eplus_path()]. The IDF must be of the same
#' version as EnergyPlus (convert older files with EnergyPlus's
#' IDFVersionUpdater). A run that ends with a fatal error fails with an
#' error of class `bayesbem_error_eplus_run` quoting EnergyPlus's error
#' file; [simulate_design()] keeps such runs apart.
#'
#' @param idf Path of the EnergyPlus model (`.idf`, or `.idf.gz`). Defaults
#'   to the shipped case-study building (EnergyPlus 25.2).
#' @param weather Path of the EPW weather file (or `.epw.gz`).
#' @param parameters A parameter table (see [bem_parameters()]) of the
#'   mapped parameters; by default the study's 14, from the map.
#' @param map The parameter map, see Details.
#' @param meter Name of a monthly `Output:Meter` of the model.
#' @param eplus Directory of EnergyPlus, see [eplus_path()].
#' @return A `bayesbem_simulator`.
#' @family simulation
#' @export
#' @examples
#' \donttest{
#' if (eplus_available()) {
#'   sim <- eplus_simulator(weather = system.file("extdata", "2013_AMY.epw.gz",
#'                                                package = "bayesbem"))
#'   simulate_design(sim, data.frame(equipment_power_density = c(10, 20)))
#' }
#' }
eplus_simulator <- function(idf = system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"),
                            weather, parameters = NULL, map = eplus_parameter_map(),
                            meter = "Electricity:Facility", eplus = NULL) {
  dir <- eplus_path(eplus)
  version <- eplus_version(dir)
  check_file(idf, "idf")
  check_file(weather, "weather")
  model <- read_idf(idf)
  check_idf_version(model, version, idf)
  map <- check_parameter_map(map, model, file.path(dir, "Energy+.idd"))
  parameters <- parameters %||% map_parameters(map)
  missing <- setdiff(parameters$parameter, map$parameter)
  if (length(missing) > 0L) {
    abort_bayesbem(c("{.arg parameters} has {.field {missing}}, which {.arg map} does not map to the model.",
                     i = "Add rows for {?it/them} to {.arg map}."),
                   "parameters")
  }
  epw <- epw_monthly(weather)
  x <- data.frame(temp = epw$temp, rh = epw$rh, solar = epw$dni)
  fun <- function(params, x) {
    run_eplus(set_idf_fields(model, map, params), weather, dir, meter, nrow(x))
  }
  name <- sprintf("EnergyPlus %s: %s (%s), %s (kWh)", version, basename(idf),
                  substr(rlang::hash(model), 1, 8), meter)
  simulator(fun, x, parameters, name = name,
            key = list(model, unname(tools::md5sum(weather)), map, meter, version))
}

#' Find EnergyPlus
#'
#' `eplus_path()` returns the directory of the EnergyPlus installation to
#' use, looking in this order: the argument `eplus`; the option
#' `bayesbem.eplus`; the environment variable `BAYESBEM_EPLUS`; the
#' installations eplusr knows (when eplusr is installed; the newest
#' version); the standard install locations (`/usr/local/EnergyPlus-*`,
#' `/Applications/EnergyPlus-*`, `C:/EnergyPlusV*`); and `energyplus` on the
#' `PATH`. `eplus_available()` says whether one is found.
#'
#' @param eplus Optional directory holding the `energyplus` executable and
#'   `Energy+.idd`.
#' @return `eplus_path()`: the directory; `eplus_available()`: `TRUE` or
#'   `FALSE`.
#' @family simulation
#' @export
#' @examples
#' eplus_available()
eplus_path <- function(eplus = NULL) {
  candidates <- c(eplus, getOption("bayesbem.eplus"), Sys.getenv("BAYESBEM_EPLUS"))
  candidates <- candidates[nzchar(candidates)]
  if (length(candidates) > 0L) {
    dir <- candidates[1]
    if (!is_eplus_dir(dir)) {
      abort_bayesbem(c("No EnergyPlus in {.path {dir}}.",
                       i = "The directory must hold the {.file energyplus} executable and {.file Energy+.idd}."),
                     "eplus_missing")
    }
    return(normalizePath(dir))
  }
  found <- Filter(is_eplus_dir, c(eplusr_dirs(), standard_eplus_dirs(),
                                  dirname(Sys.which("energyplus"))))
  if (length(found) == 0L) {
    abort_bayesbem(c("EnergyPlus was not found.",
                     i = "Install EnergyPlus, then give its directory as {.arg eplus}, in {.code options(bayesbem.eplus = )} or in the environment variable {.envvar BAYESBEM_EPLUS}.",
                     i = "The embedded monthly model, {.fn bem_simulator}, needs no external software."),
                   "eplus_missing")
  }
  normalizePath(found[[1]])
}

#' @rdname eplus_path
#' @export
eplus_available <- function(eplus = NULL) {
  !inherits(try(eplus_path(eplus), silent = TRUE), "try-error")
}

is_eplus_dir <- function(dir) {
  nzchar(dir) && file.exists(file.path(dir, "Energy+.idd")) &&
    (file.exists(file.path(dir, "energyplus")) || file.exists(file.path(dir, "energyplus.exe")))
}

# Installations eplusr has registered, newest first.
eplusr_dirs <- function() {
  if (!requireNamespace("eplusr", quietly = TRUE)) {
    return(character())
  }
  versions <- tryCatch(eplusr::avail_eplus(), error = function(e) NULL)
  dirs <- vapply(rev(as.character(versions)), function(v) {
    tryCatch(eplusr::eplus_config(v)$dir, error = function(e) "")
  }, character(1))
  dirs[nzchar(dirs)]
}

standard_eplus_dirs <- function() {
  dirs <- c(Sys.glob("/usr/local/EnergyPlus-*"), Sys.glob("/Applications/EnergyPlus-*"),
            Sys.glob("C:/EnergyPlusV*"))
  rev(sort(dirs))
}

# "25.2" from `energyplus --version` ("EnergyPlus, Version 25.2.0-cf7368216c").
eplus_version <- function(dir) {
  out <- suppressWarnings(system2(eplus_exe(dir), "--version", stdout = TRUE, stderr = TRUE))
  v <- regmatches(out, regexpr("[0-9]+\\.[0-9]+(?=\\.[0-9]+)", out, perl = TRUE))
  if (length(v) == 0L) {
    abort_bayesbem(c("{.path {eplus_exe(dir)}} did not report its version.",
                     x = "It printed: {.val {utils::head(out, 3)}}.",
                     i = "On Linux it needs the X11 client library ({.code apt-get install libx11-6})."),
                   "eplus_missing")
  }
  v[1]
}

eplus_exe <- function(dir) {
  exe <- file.path(dir, "energyplus")
  if (file.exists(exe)) exe else file.path(dir, "energyplus.exe")
}

check_file <- function(path, arg, call = rlang::caller_env()) {
  if (!is.character(path) || length(path) != 1L || !file.exists(path)) {
    abort_bayesbem(c("{.arg {arg}} must be the path of an existing file.",
                     x = "{.path {path}} does not exist."),
                   "file", call = call)
  }
}

# Runs EnergyPlus on `model` in a fresh directory and returns the monthly
# meter in kWh.
run_eplus <- function(model, weather, dir, meter, n_periods, call = rlang::caller_env()) {
  run_dir <- tempfile("eplus-")
  dir.create(run_dir)
  on.exit(unlink(run_dir, recursive = TRUE), add = TRUE)
  idf_path <- file.path(run_dir, "in.idf")
  write_idf(model, idf_path)
  epw_path <- plain_epw(weather, run_dir)
  log <- suppressWarnings(system2(eplus_exe(dir), c("-w", shQuote(epw_path), "-d", shQuote(run_dir),
                                                     "-r", shQuote(idf_path)),
                                  stdout = TRUE, stderr = TRUE))
  end <- file.path(run_dir, "eplusout.end")
  if (!file.exists(end) || !grepl("Completed Successfully", readLines(end, warn = FALSE)[1])) {
    err <- file.path(run_dir, "eplusout.err")
    severe <- if (file.exists(err)) grep("\\*\\* +(Severe|Fatal) +\\*\\*", readLines(err, warn = FALSE),
                                         value = TRUE)
    # the error file's severe lines, or else the end of EnergyPlus's output
    lines <- utils::head(trimws(if (length(severe) > 0L) severe else utils::tail(log, 3)), 5)
    abort_bayesbem(c("EnergyPlus ended with an error.",
                     stats::setNames(lines, rep("x", length(lines))),
                     i = "Check the model and the parameter values of this run."),
                   "eplus_run", call = call)
  }
  read_monthly_meter(file.path(run_dir, "eplusmtr.csv"), meter, n_periods, call = call)
}

# EnergyPlus reads plain files only: a `.gz` weather file is decompressed
# into the run directory (readLines() reads gzip itself); others are used
# where they are.
plain_epw <- function(path, run_dir) {
  if (!grepl("\\.gz$", path)) {
    return(path)
  }
  to <- file.path(run_dir, "in.epw")
  writeLines(readLines(path, warn = FALSE), to)
  to
}

# The monthly values of `meter` from ReadVarsESO's eplusmtr.csv, J to kWh.
read_monthly_meter <- function(path, meter, n_periods, call = rlang::caller_env()) {
  table <- utils::read.csv(path, check.names = FALSE)
  col <- which(startsWith(names(table), paste0(meter, " [J](Monthly)")))
  if (length(col) != 1L) {
    abort_bayesbem(c("The model reports no monthly meter {.val {meter}}.",
                     i = "Add {.code Output:Meter, {meter}, Monthly;} to the IDF, or pick one of: {.val {names(table)[-1]}}."),
                   "eplus_run", call = call)
  }
  kwh <- table[[col]] / 3.6e6
  if (length(kwh) != n_periods) {
    abort_bayesbem(c("EnergyPlus reported {length(kwh)} month{?s}, but the weather has {n_periods}.",
                     i = "Make the model's {.code RunPeriod} cover the weather file's months."),
                   "eplus_run", call = call)
  }
  kwh
}
