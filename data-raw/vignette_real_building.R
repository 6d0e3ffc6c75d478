# Precomputes vignettes/real-building.Rmd (30 runs of a year of hours of the
# embedded model, one fit, the held-out comparison and the savings: minutes)
# by rendering it with the computations switched on;
# it stores the printed results, without the fit, in
# inst/extdata/vignette-real-building.rds, which the vignette loads
# otherwise. Rerun after changing the embedded model, the fit's defaults,
# the baseline or the scenario code. Run from the package root with the
# package installed:
#   Rscript data-raw/vignette_real_building.R
source("data-raw/render_vignette.R")
render_recomputed("real-building.Rmd", BAYESBEM_REAL_BUILDING_OUT = "vignette-real-building.rds")
