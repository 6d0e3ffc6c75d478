# Morris screening of the shipped EnergyPlus model (14 parameters, r = 10,
# 150 annual runs of EnergyPlus 25.2 on the 2013 weather), shown by the
# calibration vignette, which cannot run EnergyPlus wherever it is built.
# Run from the package root with EnergyPlus found (see ?eplus_path):
#   Rscript data-raw/eplus_screening.R
library(bayesbem)
future::plan(future::multisession, workers = 2)
sim <- eplus_simulator(weather = system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
time <- system.time(screening <- screen_morris(sim, r = 10, seed = 1))
attr(screening, "simulator") <- sim$name
attr(screening, "elapsed") <- time[["elapsed"]]
saveRDS(screening, file.path("inst", "extdata", "eplus-screening.rds"))
print(screening)
print(time)
