# Benchmark: exact GP-conditional prediction of 12 new points for 1000
# posterior draws (target: under 5 s on 2 cores). Uses a short fit of the
# shipped case study only to have 1000 draws; the fit is not timed.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-predict.R
suppressPackageStartupMessages(library(bayesbem))
fit <- suppressWarnings(calibrate(seb_field, seb_sim, chains = 2, iter = 1000, seed = 1,
                                  cores = 2, refresh = 0))
newdata <- data.frame(temp = seq(1, 22, length.out = 12), rh = seq(38, 55, length.out = 12),
                      solar = seq(185, 300, length.out = 12))
set.seed(1)
times <- vapply(1:3, function(i) {
  system.time(predict(fit, newdata, ndraws = 1000))[["elapsed"]]
}, numeric(1))
cat(sprintf("predict(): 12 points x %d draws: %s s (median %.2f s; target < 5 s)\n",
            posterior::ndraws(posterior::as_draws(fit)), paste(format(times, digits = 3), collapse = ", "),
            stats::median(times)))
cat(sprintf("machine: %d cores; R %s; %s\n", parallel::detectCores(), getRversion(), Sys.Date()))
