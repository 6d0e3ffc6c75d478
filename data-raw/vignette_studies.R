# Precomputes the parameter and prior studies of vignettes/calibration.Rmd
# (the paper's Figs 4 and 5 and Table 3) by rendering the vignette with the
# studies switched on; it stores them, without their fits, in
# inst/extdata/vignette-studies.rds, which the vignette loads otherwise.
# Rerun after changing the studies, the Stan programs or the embedded model.
# Run from the package root with the package installed (about 5 minutes on
# 2 cores): Rscript data-raw/vignette_studies.R
source("data-raw/render_vignette.R")
render_recomputed("calibration.Rmd", BAYESBEM_STUDIES_OUT = "vignette-studies.rds")
