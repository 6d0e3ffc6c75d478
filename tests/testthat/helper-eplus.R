# EnergyPlus tests run when EnergyPlus is found (tools/run-tests.R points
# BAYESBEM_EPLUS to the project's shared build) and skip otherwise.
skip_if_no_eplus <- function() {
  if (!eplus_available()) {
    testthat::skip("EnergyPlus not found: set BAYESBEM_EPLUS to its directory to run this test")
  }
}

# The shipped model's EnergyPlus simulator on the 2013 weather.
seb_eplus <- function() {
  eplus_simulator(weather = shipped_epw(2013))
}
