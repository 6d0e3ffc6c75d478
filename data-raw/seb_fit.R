# Builds `seb_fit`, a small joint calibration of the case study (every
# hyperparameter sampled, which the tests of the emulator-only convergence
# hint read) shipped so that documentation examples run in seconds. Rebuild
# it whenever the Stan program's parameters change. Run from the package
# root, with the package installed: Rscript data-raw/seb_fit.R
library(bayesbem)
seb_fit <- suppressWarnings(
  calibrate(seb_field, seb_sim, chains = 2, iter = 400, seed = 2018, cores = 2, refresh = 0,
            modular = FALSE),
  classes = "bayesbem_warning_convergence"
)
save(seb_fit, file = "data/seb_fit.rda", compress = "xz", version = 2)
