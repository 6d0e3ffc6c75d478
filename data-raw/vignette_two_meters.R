# Precomputes vignettes/discrepancy.Rmd, section 7 (two meters), by
# rendering it with the computations switched on: EnergyPlus's runs of both
# meters, the virtual gas bills, the fits, their diagnosis and extension.
# It stores the gas bills and the printed results in
# inst/extdata/vignette-two-meters.rds, which the vignette prints otherwise.
# Rerun after changing the EnergyPlus model, the simulator code,
# calibrate() or the diagnosis. Run from the package root with the package
# and EnergyPlus installed (BAYESBEM_EPLUS or EnergyPlus on the PATH):
#   Rscript data-raw/vignette_two_meters.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("discrepancy.Rmd", "BAYESBEM_METERS_OUT", "vignette-two-meters.rds")
