shipped_epw <- function(year = 2013) {
  system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
}

# The Golden TMY3 file of the shared EnergyPlus folder, when present.
golden_tmy3 <- function() {
  path <- file.path("..", "..", "..", "shared", "energyplus", "WeatherData",
                    "USA_CO_Golden-NREL.724666_TMY3.epw")
  candidates <- c(Sys.getenv("BAYESBEM_TMY3"), path,
                  file.path("..", "..", "..", "..", "shared", "energyplus", "WeatherData",
                            "USA_CO_Golden-NREL.724666_TMY3.epw"))
  hit <- candidates[nzchar(candidates) & file.exists(candidates)]
  if (length(hit) == 0L) "" else normalizePath(hit[1])
}

# Writes an EPW file: the 8 header lines of `template` and the given records.
epw_with_records <- function(template, records) {
  path <- tempfile(fileext = ".epw")
  writeLines(c(readLines(template, n = 8), records), path)
  path
}
