# Precomputes the year of hours of vignettes/meter-data.Rmd (section 3) by
# rendering it with the computations switched on; it stores the printed
# fit, monthly totals and savings in inst/extdata/vignette-meter-year.rds,
# which the vignette prints otherwise. Rerun after changing the embedded
# hourly model, calibrate()'s defaults or the prediction code. Run from the
# package root with the package installed:
#   Rscript data-raw/vignette_meter_year.R
source("data-raw/render_vignette.R")
render_recomputed("meter-data.Rmd", BAYESBEM_METER_YEAR_OUT = "vignette-meter-year.rds")
