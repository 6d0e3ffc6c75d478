# Benchmark: bills on their own dates against calendar months, known
# truth. Each problem: two meters of the embedded model on the 2013
# weather, electricity and gas, each read on its own days: twelve bills
# whose periods start on a day drawn from 1-20 January and run 26 to 35
# days each (drawn), at parameters drawn in the middle 80 % of their
# ranges, plus noise summed from independent daily errors (a bill of the
# mean length: sd 2 % of the meter's mean bill); 15 runs of a Latin
# hypercube in the three parameters; calibrate()'s defaults. Two fits of
# the same bills: on their real periods (bem_simulator(periods = ), a
# list by meter), and as a user without that option would, each bill
# taken for the calendar month its period mostly covers (bem_simulator()
# by month). Reported: the share of the 90 % intervals that hold the true
# parameters (target 85-95 % with the real periods), convergence, the
# median posterior sd.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-bill-dates.R [problems]   (default 20)
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
problems <- seq_len(if (length(args) > 0L) as.integer(args[1]) else 20L)
epw <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
params <- c("equipment_power_density", "infiltration_per_exterior_area", "heating_setpoint")
ranges <- bem_parameters()[bem_parameters()$parameter %in% params, ]
meters <- c("electricity", "gas")
monthly <- bem_simulator(epw, output = meters)

# Twelve bills from a day in 1-20 January, each 26-35 days long.
shifted_bills <- function() {
  lengths <- sample(26:35, 12, replace = TRUE)
  start <- as.Date("2013-01-01") + sample(0:19, 1) + c(0, cumsum(lengths)[-12])
  bills <- data.frame(start = start, end = start + lengths - 1)
  bills[bills$end <= as.Date("2013-12-31"), ]
}

# Draws of the parameters, converged or not, and each truth's coverage.
summarise_fit <- function(fit, truth) {
  draws <- posterior::as_draws_matrix(fit)
  conv <- check_convergence(fit, warn = FALSE)
  covered <- vapply(names(truth), function(p) {
    q <- stats::quantile(draws[, p], c(0.05, 0.95))
    truth[[p]] >= q[1] && truth[[p]] <= q[2]
  }, logical(1))
  sd_ratio <- vapply(names(truth), function(p) {
    stats::sd(draws[, p]) / (ranges$max - ranges$min)[ranges$parameter == p]
  }, numeric(1))
  list(covered = covered, converged = all(conv$ok) && sum(attr(conv, "sampler")$divergent) == 0,
       sd_ratio = sd_ratio)
}

# Each bill's calendar month: the one holding most of its days.
bill_month <- function(bills) {
  as.integer(format(bills$start + as.integer(bills$end - bills$start) %/% 2L, "%m"))
}

rows <- lapply(problems, function(k) {
  set.seed(2000 + k)
  truth <- as.list(stats::setNames(stats::runif(3, ranges$min + 0.2 * (ranges$max - ranges$min),
                                                ranges$max - 0.2 * (ranges$max - ranges$min)),
                                   ranges$parameter))
  bills <- list(electricity = shifted_bills(), gas = shifted_bills())
  real <- bem_simulator(epw, output = meters, periods = bills)
  design <- design_lhs(ranges, n = 15, seed = k)
  clean <- simulate_field(real, truth, noise_sd = 0, seed = k)
  # each meter's own bills among the union of periods, with its noise:
  # daily errors summed, a bill of the mean length at 2 % of the mean bill
  field <- do.call(rbind, lapply(meters, function(m) {
    own <- clean[clean$output == m, ][match(bills[[m]]$start, real$periods$start), ]
    days <- as.numeric(bills[[m]]$end - bills[[m]]$start) + 1
    own$y <- own$y + stats::rnorm(nrow(own), 0, 0.02 * mean(own$y) * sqrt(days / mean(days)))
    own
  }))
  fit_real <- suppressWarnings(calibrate(field, simulate_design(real, design), seed = k, refresh = 0),
                               classes = "bayesbem_warning_convergence")
  # the same bills as calendar months (two bills on one month: the first kept)
  field_month <- do.call(rbind, lapply(meters, function(m) {
    month <- bill_month(bills[[m]])
    keep <- !duplicated(month)
    data.frame(output = m, y = field$y[field$output == m][keep], monthly$x[month[keep], ])
  }))
  fit_month <- suppressWarnings(calibrate(field_month, simulate_design(monthly, design),
                                          seed = k, refresh = 0),
                                classes = "bayesbem_warning_convergence")
  out <- lapply(list(real = fit_real, month = fit_month), summarise_fit, truth = truth)
  cat(sprintf("problem %d: real periods %d/3 covered, calendar months %d/3\n", k,
              sum(out$real$covered), sum(out$month$covered)))
  out
})

table <- do.call(rbind, lapply(c("real", "month"), function(route) {
  covered <- do.call(rbind, lapply(rows, function(r) r[[route]]$covered))
  data.frame(periods = c(real = "the bills' own", month = "calendar months")[[route]],
             problems = length(rows),
             converged = sum(vapply(rows, function(r) r[[route]]$converged, logical(1))),
             covered = sprintf("%d/%d (%.0f %%)", sum(covered), length(covered),
                               100 * mean(covered)),
             per_parameter = paste(colSums(covered), collapse = " / "),
             sd_over_range = paste(sprintf("%.3f", apply(do.call(rbind, lapply(rows, function(r) {
               r[[route]]$sd_ratio
             })), 2, stats::median)), collapse = " / "))
}))
cat("\nparameters:", paste(ranges$parameter, collapse = " / "), "\n")
print(table, row.names = FALSE)
cat(sprintf("\nmachine: %d cores; R %s; %s\n", parallel::detectCores(), getRversion(), Sys.Date()))
