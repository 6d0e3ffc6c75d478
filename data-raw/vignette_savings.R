# Precomputes vignettes/savings.Rmd (about 150 EnergyPlus runs and a fit,
# about 10 minutes on 2 cores) by rendering it with the computations switched
# on; it stores the printed results, without the fit, in
# inst/extdata/vignette-savings.rds, which the vignette loads otherwise.
# Rerun after changing the EnergyPlus model, the fit's defaults or the
# scenario code. Run from the package root with the package and EnergyPlus
# installed (BAYESBEM_EPLUS or EnergyPlus on the PATH):
#   Rscript data-raw/vignette_savings.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("savings.Rmd", BAYESBEM_SAVINGS_OUT = "vignette-savings.rds")
