# Builds `seb_fit`, a small calibration of the case study shipped so that
# documentation examples run in seconds. Rebuild it whenever the Stan
# program's parameters change. Run from the package root, with the package
# installed: Rscript data-raw/seb_fit.R
library(bayesbem)
seb_fit <- suppressWarnings(
  calibrate(seb_field, seb_sim, chains = 2, iter = 400, seed = 2018, cores = 2, refresh = 0),
  classes = "bayesbem_warning_convergence"
)
save(seb_fit, file = "data/seb_fit.rda", compress = "xz", version = 2)
