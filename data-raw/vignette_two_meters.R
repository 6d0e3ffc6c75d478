# Precomputes the EnergyPlus data of vignettes/discrepancy.Rmd, section 7
# (two meters) by rendering it with the computations switched on; it stores
# the runs of both meters, the virtual gas bills and the parameters they
# were simulated at in inst/extdata/vignette-two-meters.rds, which the
# vignette loads otherwise (it fits and diagnoses them itself). Rerun after
# changing the EnergyPlus model or the simulator code. Run from the package
# root with the package and EnergyPlus installed (BAYESBEM_EPLUS or
# EnergyPlus on the PATH):
#   Rscript data-raw/vignette_two_meters.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("discrepancy.Rmd", "BAYESBEM_METERS_OUT", "vignette-two-meters.rds")
