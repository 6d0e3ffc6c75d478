# Precomputes vignettes/discrepancy.Rmd, section 6 (the virtual building),
# by rendering it with the computations switched on: EnergyPlus's runs, the
# fit, its diagnosis and the extension's gain. It stores their printed
# results in inst/extdata/vignette-virtual-building.rds, which the vignette
# prints otherwise. Rerun after changing the EnergyPlus model, the
# simulator code, calibrate() or the diagnosis. Run from the package root
# with the package and EnergyPlus installed (BAYESBEM_EPLUS or EnergyPlus
# on the PATH):
#   Rscript data-raw/vignette_virtual_building.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("discrepancy.Rmd", "BAYESBEM_VIRTUAL_OUT", "vignette-virtual-building.rds")
