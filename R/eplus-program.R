# The EnergyPlus installation: finding it, its version, and running its
# programs (energyplus, ConvertInputFormat, ExpandObjects) under a time
# limit with their error files read.

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
#' @family EnergyPlus
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

# One call of the energyplus executable under a time limit; `ok` when it
# completed successfully (eplusout.end says so).
run_energyplus <- function(eplus, args, dir, timeout) {
  start <- Sys.time()
  out <- run_program(eplus_exe(eplus), args, dir, timeout)
  end <- file.path(dir, "eplusout.end")
  ok <- !out$timeout && file.exists(end) &&
    grepl("Completed Successfully", readLines(end, warn = FALSE)[1])
  list(ok = ok, timeout = out$timeout, limit = ceiling(timeout), dir = dir,
       output = out$output, time = as.numeric(difftime(Sys.time(), start, units = "secs")))
}

# A program run from `wd` under a time limit (whole seconds, rounded up),
# with its output. Base system2() rather than processx: processx replaces
# R's SIGCHLD handler, after which the forked chains of calibrate() are no
# longer reaped ("Error while shutting down parallel", r-lib/processx#236).
run_program <- function(exe, args, wd, timeout) {
  old <- setwd(wd)
  on.exit(setwd(old), add = TRUE)
  output <- suppressWarnings(system2(exe, shQuote(args), stdout = TRUE, stderr = TRUE,
                                     timeout = ceiling(timeout)))
  status <- attr(output, "status") %||% 0L
  list(status = status, timeout = identical(as.integer(status), 124L), output = as.vector(output))
}

# EnergyPlus's messages are quoted, not interpolated (they hold braces).
abort_eplus_errors <- function(result, what, ..., call = rlang::caller_env(),
                               .envir = parent.frame()) {
  errors <- read_err(file.path(result$dir, "eplusout.err"))
  lines <- errors$message[errors$level %in% c("Severe", "Fatal")]
  if (result$timeout) {
    lines <- c(sprintf("the run took longer than its time limit of %s s", format(result$limit)),
               lines)
  }
  if (length(lines) == 0L) lines <- utils::tail(result$output, 3)
  lines <- gsub("}", "}}", gsub("{", "{{", utils::head(lines, 6), fixed = TRUE), fixed = TRUE)
  abort_bayesbem(c(what, stats::setNames(lines, rep("x", length(lines))), ...),
                 "eplus_run", errors = errors, call = call, .envir = .envir)
}

# EnergyPlus's error file as a table: each "** Warning **", "** Severe **"
# or "** Fatal **" line with its "**   ~~~   **" continuation lines.
read_err <- function(path) {
  lines <- if (file.exists(path)) readLines(path, warn = FALSE) else character()
  head <- regmatches(lines, regexec("^\\s*\\*\\*\\s*(Warning|Severe|Fatal)\\s*\\*\\*\\s?(.*)$", lines))
  is_head <- lengths(head) == 3L
  more <- grepl("^\\s*\\*\\*\\s*~~~\\s*\\*\\*", lines)
  group <- cumsum(is_head)
  keep <- (is_head | more) & group > 0L
  text <- ifelse(is_head, vapply(head, function(h) if (length(h) == 3L) h[3] else "", ""),
                 trimws(sub("^\\s*\\*\\*\\s*~~~\\s*\\*\\*", "", lines)))
  data.frame(level = vapply(head[is_head], `[`, "", 2),
             message = as.vector(tapply(trimws(text[keep]), group[keep], paste, collapse = " ")),
             stringsAsFactors = FALSE)
}

# EnergyPlus reads plain files only: a `.gz` file is decompressed into `dir`
# (readLines() reads gzip itself); others are used where they are.
plain_file <- function(path, dir) {
  if (!grepl("\\.gz$", path)) {
    return(normalizePath(path))
  }
  to <- file.path(dir, basename(sub("\\.gz$", "", path)))
  writeLines(readLines(path, warn = FALSE), to)
  to
}
