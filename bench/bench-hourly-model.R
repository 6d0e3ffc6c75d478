# Benchmark: the hourly embedded model (bem_hourly(), 5R1C) against the
# monthly one (bem_monthly()) on the shipped 2012 and 2013 weather: the
# relative difference of annual and monthly totals, at the initial
# parameters and over a 30-point Latin hypercube of the 14 parameters'
# ranges; and the time of a year's simulation (target: well under 1 s).
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-hourly-model.R
suppressPackageStartupMessages(library(bayesbem))
pars <- bem_parameters()
initial <- stats::setNames(as.list(pars$initial), pars$parameter)
design <- design_lhs(pars, 30, seed = 1)
differences <- function(p, hourly, monthly) {
  h <- bem_hourly(p, hourly)
  m <- bem_monthly(p, monthly)
  elec <- as.vector(tapply(h$electricity, hourly$month, sum))
  gas <- as.vector(tapply(h$gas, hourly$month, sum))
  heating <- m$gas > 0.1 * max(m$gas)
  c(annual_electricity = sum(elec) / sum(m$electricity) - 1,
    annual_gas = sum(gas) / sum(m$gas) - 1,
    worst_month_electricity = max(abs(elec / m$electricity - 1)),
    worst_heating_month_gas = max(abs(gas[heating] / m$gas[heating] - 1)))
}
rows <- list()
for (year in c(2012, 2013)) {
  epw <- system.file("extdata", sprintf("%d_AMY.epw.gz", year), package = "bayesbem")
  hourly <- epw_weather(epw, by = "hour")
  monthly <- epw_monthly(epw)
  at_initial <- differences(initial, hourly, monthly)
  over <- vapply(seq_len(nrow(design)), function(i) {
    p <- utils::modifyList(initial, as.list(design[i, ]))
    differences(p, hourly, monthly)
  }, numeric(4))
  for (k in names(at_initial)) {
    rows[[length(rows) + 1L]] <- data.frame(
      year = year, quantity = k, initial = round(100 * at_initial[[k]], 1),
      lhs_median = round(100 * stats::median(over[k, ]), 1),
      lhs_min = round(100 * min(over[k, ]), 1), lhs_max = round(100 * max(over[k, ]), 1))
  }
  times <- vapply(1:5, function(i) system.time(bem_hourly(initial, hourly))[["elapsed"]], numeric(1))
  cat(sprintf("%d: a year of hours (%d) in %.3f s (median of 5)\n", year, nrow(hourly),
              stats::median(times)))
}
cat("\nhourly minus monthly, % of the monthly model's (worst: absolute)\n")
print(do.call(rbind, rows), row.names = FALSE)
cat(sprintf("\nmachine: %d cores; R %s; %s\n", parallel::detectCores(), getRversion(), Sys.Date()))
