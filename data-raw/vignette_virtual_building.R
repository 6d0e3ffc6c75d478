# Precomputes the EnergyPlus data of vignettes/discrepancy.Rmd, section 6
# (the virtual building) by rendering
# it with the computations switched on; it stores the field data, the runs,
# the weekend flags and the truth in inst/extdata/vignette-virtual-building.rds,
# which the vignette loads otherwise (it fits and diagnoses them itself).
# Rerun after changing the EnergyPlus model or the simulator code. Run from
# the package root with the package and EnergyPlus installed (BAYESBEM_EPLUS
# or EnergyPlus on the PATH):
#   Rscript data-raw/vignette_virtual_building.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("discrepancy.Rmd", "BAYESBEM_VIRTUAL_OUT", "vignette-virtual-building.rds")
