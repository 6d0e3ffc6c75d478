# Precomputes vignettes/discrepancy.Rmd, sections 6 (the virtual building)
# and 7 (two meters), in one render with the computations switched on:
# EnergyPlus's runs, the fits, their diagnoses and extensions. It stores the
# printed results (and the virtual gas bills) in
# inst/extdata/vignette-virtual-building.rds and vignette-two-meters.rds,
# which the vignette prints otherwise. Rerun after changing the EnergyPlus
# model, the simulator code, calibrate() or the diagnosis. Run from the
# package root with the package and EnergyPlus installed (BAYESBEM_EPLUS or
# EnergyPlus on the PATH):
#   Rscript data-raw/vignette_discrepancy.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("discrepancy.Rmd", BAYESBEM_VIRTUAL_OUT = "vignette-virtual-building.rds",
                  BAYESBEM_METERS_OUT = "vignette-two-meters.rds")
