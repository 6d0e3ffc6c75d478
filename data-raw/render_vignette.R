# Shared by the data-raw/vignette_*.R scripts: renders a vignette with its
# precomputed chunks switched on (BAYESBEM_RECOMPUTE) and its save chunk
# writing inst/extdata/<file>, whose path it reads from the environment
# variable `out_var`. Run from the package root.
render_recomputed <- function(vignette, out_var, file) {
  path <- file.path(normalizePath("inst/extdata"), file)
  do.call(Sys.setenv, stats::setNames(list("true", path), c("BAYESBEM_RECOMPUTE", out_var)))
  rmarkdown::render(file.path("vignettes", vignette), output_dir = tempdir(), quiet = TRUE)
  cat("Saved", path, "\n")
}
