# Benchmark (issue 16): coverage of the true calibration parameters by their
# 90 % intervals before and after extend() with the cause that
# explain_discrepancy() names. Synthetic problems of the test suite
# (tests/testthat/helper-synthetic.R: 48 months, equipment power density
# and infiltration calibrated, 30 runs, 36 months fitted), a hidden effect
# of each kind (humidity step, occupancy, equipment step, occupancy only in
# warm months) in turn, one noise draw per problem; the named candidate (an
# input, a covariate, or with `regions` a region of them) enters as a
# linear discrepancy term; when nothing is named the fit is kept.
# Usage, from the package root with bayesbem installed:
#   Rscript bench/bench-extension-coverage.R [problems, default 9] [regions: TRUE or FALSE, default FALSE]
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
problems <- if (length(args) > 0) as.integer(args[1]) else 9L
regions <- length(args) > 1 && as.logical(args[2])
for (f in c("helper-seed.R", "helper-weather.R", "helper-synthetic.R")) {
  sys.source(file.path("tests", "testthat", f), envir = globalenv())
}
kinds <- c("input", "covariate", "step", if (regions) "interaction")
covered <- function(fit) {
  s <- summary(fit)$parameters
  truth <- unlist(synthetic_truth)[rownames(s)]
  s$q5 <= truth & truth <= s$q95
}
rows <- lapply(seq_len(problems), function(i) {
  kind <- kinds[(i - 1) %% length(kinds) + 1]
  case <- make_synthetic_case(kind, noise_seed = 200 + i)
  ex <- explain_discrepancy(case$base, case$train_covariates, n_null = 1000, seed = i,
                            regions = regions)
  cause <- if (any(ex$explains)) ex$candidate[1] else NA_character_
  before <- covered(case$base)
  after <- if (is.na(cause)) before else {
    ext <- suppressWarnings(extend(case$base, with = cause, covariates = case$train_covariates,
                                   refresh = 0),
                            classes = "bayesbem_warning_convergence")
    covered(ext)
  }
  cat(sprintf("problem %d (%s, noise seed %d): named %s; covered before %s, after %s\n", i, kind,
              200 + i, cause, paste(before, collapse = "/"), paste(after, collapse = "/")))
  data.frame(problem = i, effect = kind, named = cause, covered_before = sum(before),
             covered_after = sum(after), parameters = length(before))
})
out <- do.call(rbind, rows)
print(out, row.names = FALSE)
cat(sprintf("\ncoverage of the 90 %% intervals: before %d/%d (%.0f %%), after %d/%d (%.0f %%); worse after extension in %d problem(s)\n",
            sum(out$covered_before), sum(out$parameters), 100 * mean(out$covered_before / out$parameters),
            sum(out$covered_after), sum(out$parameters), 100 * mean(out$covered_after / out$parameters),
            sum(out$covered_after < out$covered_before)))
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\n", Sys.info()[["nodename"]],
            parallel::detectCores(), getRversion(), packageVersion("rstan"), Sys.Date()))
