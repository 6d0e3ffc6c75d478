# Precomputes vignettes/smart-meter-fault.Rmd (about 200 EnergyPlus runs of a
# year of hours, three fits and a diagnosis: about an hour on 2 cores) by
# rendering it with the computations switched on; it stores the printed
# results, without the fits, in inst/extdata/vignette-smart-meter.rds, which
# the vignette loads otherwise. Rerun after changing the EnergyPlus model,
# the fit's defaults, the diagnosis or the scenario code. Run from the
# package root with the package and EnergyPlus installed (BAYESBEM_EPLUS or
# EnergyPlus on the PATH):
#   Rscript data-raw/vignette_smart_meter.R
stopifnot(bayesbem::eplus_available())
source("data-raw/render_vignette.R")
render_recomputed("smart-meter-fault.Rmd", BAYESBEM_SMART_METER_OUT = "vignette-smart-meter.rds")
