# Builds the shipped case-study datasets `seb_field` and `seb_sim` from the
# bc-stan files (MIT, see inst/COPYRIGHTS). Run from the package root:
#   Rscript data-raw/seb.R
field <- utils::read.csv("data-raw/DATAFIELD.csv")
sim <- utils::read.csv("data-raw/DATACOMP.csv")
stopifnot(nrow(field) == 12L, ncol(field) == 4L, nrow(sim) == 120L, ncol(sim) == 7L)

x_names <- c("temp", "rh", "solar")
seb_field <- stats::setNames(field, c("y", x_names))
# the field months are January to December 2013 (the 2013 weather file)
seb_field$month <- as.Date(sprintf("2013-%02d-01", 1:12))
seb_sim <- stats::setNames(sim, c("eta", x_names, "fan_total_efficiency",
                                  "equipment_power_density",
                                  "infiltration_per_exterior_area"))

save(seb_field, file = "data/seb_field.rda", compress = "xz", version = 2)
save(seb_sim, file = "data/seb_sim.rda", compress = "xz", version = 2)
