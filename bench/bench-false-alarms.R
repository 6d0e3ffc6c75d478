# Benchmark (issues 6, 16): how often explain_discrepancy() names a cause
# when nothing is hidden, and how often it finds a hidden cause, without
# and with region terms (regions = TRUE) on the same fits. The synthetic
# problem of the test suite (tests/testthat/helper-synthetic.R: 48 months,
# two parameters, 30 runs, 36 months fitted), one fit per noise draw; the
# candidates are the three inputs, an occupancy covariate, a step at month
# 15 and two decoys; the interaction is occupancy's effect only where
# temp > 15. Prints, per kind of data, the share of draws in which some
# candidate was named, and in which the true cause ranked first and was
# named (a region or threshold of the cause, "rh > 47", counts as the
# cause; for the interaction only "occupancy, where temp > ..." does).
# Usage, from the package root with bayesbem installed:
#   Rscript bench/bench-false-alarms.R [noise draws per kind, default 10] [kinds, comma-separated]
# With BENCH_FITS=<folder>, each fit is saved there and reused by later runs.
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
draws <- if (length(args) > 0) as.integer(args[1]) else 10L
for (f in c("helper-seed.R", "helper-weather.R", "helper-synthetic.R")) {
  sys.source(file.path("tests", "testthat", f), envir = globalenv())
}
causes <- c(none = NA, input = "^rh($| |,)", covariate = "^occupancy($| |,)",
            step = "^after_change($| |,)", interaction = "^occupancy, where temp >")
if (length(args) > 1) causes <- causes[strsplit(args[2], ",")[[1]]]
cached_case <- function(kind, seed) {
  folder <- Sys.getenv("BENCH_FITS")
  file <- file.path(folder, sprintf("%s_%d.rds", kind, seed))
  if (nzchar(folder) && file.exists(file)) {
    return(readRDS(file))
  }
  case <- make_synthetic_case(kind, noise_seed = seed)[c("base", "train_covariates")]
  if (nzchar(folder)) saveRDS(case, file)
  case
}
rows <- list()
for (kind in names(causes)) {
  outcome <- vapply(seq_len(draws), function(i) {
    case <- cached_case(kind, 100 + i)
    result <- vapply(c(FALSE, TRUE), function(regions) {
      ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 1000, seed = i,
                                regions = regions)
      named <- ex$candidate[ex$explains]
      region <- grepl(", where | [<>] ", ex$candidate)
      best_region <- if (any(region)) {
        sprintf("; best region: %s, p %.3f", ex$candidate[region][which.min(ex$p_value[region])],
                min(ex$p_value[region]))
      } else {
        ""
      }
      cat(sprintf("%s, noise seed %d, regions %s: named %s (top: %s, share %.2f, p %.3f%s)\n",
                  kind, 100 + i, regions,
                  if (length(named) > 0) paste(utils::head(named, 4), collapse = ", ") else "nothing",
                  ex$candidate[1], ex$share[1], ex$p_value[1], best_region))
      c(named = length(named) > 0,
        found = !is.na(causes[[kind]]) && grepl(causes[[kind]], ex$candidate[1]) &&
          ex$explains[1])
    }, logical(2))
    as.vector(result)
  }, logical(4))
  rows[[kind]] <- data.frame(data = kind, draws = draws,
                             cause_named = mean(outcome[1, ]),
                             true_cause_found = if (is.na(causes[[kind]])) NA else mean(outcome[2, ]),
                             cause_named_regions = mean(outcome[3, ]),
                             true_cause_found_regions = if (is.na(causes[[kind]])) NA else mean(outcome[4, ]))
}
cat("\nShare of noise draws (alpha = 0.05, max-statistic adjustment over the 7 candidates, or with regions within candidates and regions, alpha shared 0.8/0.2; 1000 simulated null residuals):\n")
print(do.call(rbind, rows), row.names = FALSE)
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\n", Sys.info()[["nodename"]],
            parallel::detectCores(), getRversion(), packageVersion("rstan"), Sys.Date()))
