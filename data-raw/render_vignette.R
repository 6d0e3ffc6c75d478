# Shared by the data-raw/vignette_*.R scripts: renders a vignette with its
# precomputed chunks switched on (BAYESBEM_RECOMPUTE) and its save chunks
# writing inst/extdata/<file>, each save chunk reading its path from an
# environment variable: `...` names each variable with its file. Run from
# the package root.
render_recomputed <- function(vignette, ...) {
  files <- c(...)
  paths <- file.path(normalizePath("inst/extdata"), files)
  do.call(Sys.setenv, as.list(c(BAYESBEM_RECOMPUTE = "true", stats::setNames(paths, names(files)))))
  rmarkdown::render(file.path("vignettes", vignette), output_dir = tempdir(), quiet = TRUE)
  cat("Saved", paths, sep = "\n")
}
