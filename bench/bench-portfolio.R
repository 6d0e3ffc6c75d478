# Benchmark: portfolios of buildings with known truth (calibrate_portfolio()).
# Each building: the embedded monthly model under 2013's weather with its
# own true equipment power density and infiltration (uniform over their
# ranges' middle), twelve bills with 3 % noise, 10 runs over the two
# parameters, calibrate()'s defaults, the savings of equipment x 0.7 over
# the year (20 draws). The true savings: the model at the truth, baseline
# less retrofit.
#   coverage: over P portfolios of B buildings, how often the 90 %
#     interval of the portfolio's total holds the true total, and how often
#     Guideline 14's aggregate FSU (total +- FSU x total) does, and how
#     many buildings' own 90 % intervals hold their true savings
#     (BENCH_LAMBDA_DELTA, below, sets the discrepancy's prior);
#   timing: a portfolio of N buildings on 1 and on 2 local workers
#     (multisession): wall time, buildings per hour, scaling efficiency
#     (T1 / (2 T2)), the buildings' jobs' own seconds summed, and the wall
#     time beyond that sum over the workers.
#   real: N real buildings of the Cambridge archive (bench/archive.R), each
#     its 2019 electricity as monthly bills: the hourly readings through
#     field_hours() (what stands for missing left out), each month with at
#     least 95 % of its hours present summed and scaled to all its hours;
#     the embedded monthly model over Bedford's weather of a university
#     building (bem_building_facts(type = "university"), bem_parameters(type
#     = "university")) of four floors, uncooled, a ventilation-only fan, its
#     floor area the year's use over CIBSE TM46's 80 kWh/m2; 20 runs over
#     equipment, lighting and fan efficiency made in each job; the savings
#     of a fifth less plug load. On 2 workers: the table by building, the
#     total, wall time and buildings per hour.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-portfolio.R coverage [P] [B]    (default 20 10; BENCH_WORKERS,
#                                                       default 2; BENCH_FROM, the first
#                                                       portfolio, default 1: a stopped
#                                                       run goes on where it stopped)
#   Rscript bench/bench-portfolio.R timing [N]          (default 20)
#   BENCH_ARCHIVE=<the archive's git directory> Rscript bench/bench-portfolio.R real [N]
#                                                       (default 10: the first N of
#                                                       buildings 0, 1, 2, ... with a
#                                                       2019 electricity meter)
suppressPackageStartupMessages(library(bayesbem))
options(bayesbem.progress = FALSE)
args <- commandArgs(trailingOnly = TRUE)
what <- if (length(args) > 0L) args[1] else "coverage"
sim <- bem_simulator(system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem"))
pars <- sim$parameters[sim$parameters$parameter %in% c("equipment_power_density",
                                                       "infiltration_per_exterior_area"), ]
# BENCH_RUNS: the runs of the synthetic buildings (10 unless set)
runs <- simulate_design(sim, design_lhs(pars, as.integer(Sys.getenv("BENCH_RUNS", "10")), seed = 1))
retrofit <- function(s) scenario(s, scale = c(equipment_power_density = 0.7))

# Building b's 2019 electricity as monthly bills on the embedded monthly
# model (see "real" above), or NULL when the archive has no such meter or
# fewer than 6 months are covered.
real_building <- function(b, hourly, epw) {
  readings <- archive_meter(b, "electricity", "2019")
  if (is.null(readings)) return(NULL)
  time <- as.POSIXct(readings[[1]], tz = "UTC")
  field <- tryCatch(suppressWarnings(suppressMessages(
    field_hours(hourly, time, readings[[2]], sufficiency = 0))), error = function(e) NULL)
  if (is.null(field)) return(NULL)
  cover <- data_sufficiency(field$time, as.POSIXct(c("2019-01-01", "2019-12-31 23:00"), tz = "UTC"))
  months <- cover$month[cover$share >= 0.95]
  if (length(months) < 6L) return(NULL)
  month_of <- format(field$time, "%Y-%m", tz = "UTC")
  use <- vapply(months, function(m) sum(field$y[month_of == m]), numeric(1)) /
    cover$share[match(months, cover$month)]
  periods <- bem_simulator(epw)$periods
  periods <- periods[format(periods$start, "%Y-%m") %in% months, ]
  area <- sum(use) * 12 / length(months) / 80
  building <- bem_building_facts(area, floors = 4, type = "university", cooling = FALSE,
                                 fan_flow = 1e-3 * area)
  sim <- bem_simulator(epw, parameters = bem_parameters(type = "university"),
                       building = building, periods = periods)
  vary <- sim$parameters[sim$parameters$parameter %in% c("equipment_power_density",
                                                         "lighting_power_density",
                                                         "fan_total_efficiency"), ]
  list(field = data.frame(y = unname(use), sim$x), simulator = sim,
       design = design_lhs(vary, 20, seed = 1), months = length(months), area = area)
}

# B buildings of portfolio p with their true savings.
portfolio <- function(p, b) {
  set.seed(1000 * p)
  truth <- data.frame(equipment_power_density = stats::runif(b, 8, 25),
                      infiltration_per_exterior_area = stats::runif(b, 3e-4, 1.2e-3))
  fields <- lapply(seq_len(b), function(k) {
    use <- simulate_design(sim, truth[k, ])$eta
    data.frame(y = use * (1 + stats::rnorm(12, sd = 0.03)), sim$x)
  })
  true_savings <- vapply(seq_len(b), function(k) {
    after <- truth[k, ]
    after$equipment_power_density <- 0.7 * after$equipment_power_density
    sum(simulate_design(sim, truth[k, ])$eta) - sum(simulate_design(sim, after)$eta)
  }, numeric(1))
  buildings <- data.frame(id = sprintf("p%02d-b%02d", p, seq_len(b)))
  buildings$field <- fields
  buildings$runs <- rep(list(runs), b)
  buildings$simulator <- rep(list(sim), b)
  list(buildings = buildings, true_total = sum(true_savings), true_savings = true_savings)
}

# BENCH_LAMBDA_DELTA="shape,rate": the discrepancy precision's Gamma prior
# (koh_priors()'s default unless set), e.g. "1e4,1" for a discrepancy held
# near zero, to see how much of the intervals' width it makes.
lambda_delta <- Sys.getenv("BENCH_LAMBDA_DELTA")
priors <- if (nzchar(lambda_delta)) {
  koh_priors(lambda_delta = as.numeric(strsplit(lambda_delta, ",")[[1]]))
} else koh_priors()

run <- function(buildings, workers, dir, retrofit) {
  # plan() reads its argument unevaluated: give it a variable
  strategy <- if (workers == 1L) future::sequential else
    future::tweak(future::multisession, workers = workers)
  future::plan(strategy)
  on.exit(future::plan(future::sequential))
  started <- proc.time()[["elapsed"]]
  p <- suppressMessages(calibrate_portfolio(buildings, dir, retrofit = retrofit, ndraws = 20,
                                            cores = 1L, priors = priors))
  list(portfolio = p, seconds = proc.time()[["elapsed"]] - started)
}

if (what == "coverage") {
  n_portfolios <- if (length(args) > 1L) as.integer(args[2]) else 20L
  n_buildings <- if (length(args) > 2L) as.integer(args[3]) else 10L
  first <- as.integer(Sys.getenv("BENCH_FROM", "1"))
  rows <- lapply(seq(first, n_portfolios), function(p) {
    problem <- portfolio(p, n_buildings)
    workers <- as.integer(Sys.getenv("BENCH_WORKERS", "2"))
    result <- run(problem$buildings, workers, file.path(tempdir(), sprintf("portfolio-%02d", p)),
                  retrofit)
    total <- summary(result$portfolio)$total
    half_g14 <- total$fsu_guideline14 * abs(total$savings)
    each <- summary(result$portfolio)$buildings
    row <- data.frame(portfolio = p, buildings = total$buildings, truth = problem$true_total,
                      savings = total$savings, lower = total$lower, upper = total$upper,
                      covered = problem$true_total >= total$lower &&
                        problem$true_total <= total$upper,
                      fsu = total$fsu, fsu_g14 = total$fsu_guideline14,
                      covered_g14 = abs(problem$true_total - total$savings) <= half_g14,
                      buildings_covered = sum(problem$true_savings >= each$lower &
                                                problem$true_savings <= each$upper),
                      seconds = round(result$seconds))
    # each portfolio's row as it finishes, so that a stopped run still tells
    print(row, row.names = FALSE, digits = 4)
    row
  })
  table <- do.call(rbind, rows)
  print(table, row.names = FALSE, digits = 4)
  cat(sprintf("\n90 %% interval of the total holds the truth in %d of %d portfolios; Guideline 14's FSU in %d of %d\n",
              sum(table$covered), nrow(table), sum(table$covered_g14), nrow(table)))
  cat(sprintf("each building's own 90 %% interval holds its truth in %d of %d buildings\n",
              sum(table$buildings_covered), sum(table$buildings)))
} else if (what == "real") {
  archive <- Sys.getenv("BENCH_ARCHIVE")
  if (!nzchar(archive)) stop("set BENCH_ARCHIVE to the archive's folder", call. = FALSE)
  source(file.path("bench", "archive.R"))
  n <- if (length(args) > 1L) as.integer(args[2]) else 10L
  epw <- archive_epw("2019")
  hourly <- bem_simulator(epw, by = "hour")
  found <- list()
  for (b in setdiff(as.character(0:120), held_for_acceptance)) {
    if (length(found) == n) break
    one <- real_building(b, hourly, epw)
    if (!is.null(one)) found[[b]] <- one
  }
  buildings <- data.frame(id = paste0("b", names(found)))
  for (col in c("field", "simulator", "design")) buildings[[col]] <- lapply(found, `[[`, col)
  result <- run(buildings, 2L, file.path(tempdir(), "real"),
                function(s) scenario(s, scale = c(equipment_power_density = 0.8)))
  table <- summary(result$portfolio)$buildings
  table$months <- vapply(found, `[[`, integer(1), "months")
  table$floor_area <- round(vapply(found, `[[`, numeric(1), "area"))
  print(table[setdiff(names(table), "error")], row.names = FALSE, digits = 3)
  print(summary(result$portfolio)$total, row.names = FALSE, digits = 4)
  cat(sprintf("\n%d buildings on 2 workers: %.0f s, %.0f buildings an hour\n", nrow(buildings),
              result$seconds, 3600 * nrow(buildings) / result$seconds))
} else {
  n <- if (length(args) > 1L) as.integer(args[2]) else 20L
  problem <- portfolio(1L, n)
  runs <- lapply(1:2, function(w) {
    run(problem$buildings, w, file.path(tempdir(), sprintf("timing-%d", w)), retrofit)
  })
  times <- vapply(runs, `[[`, numeric(1), "seconds")
  # each building's own seconds (its job, in its worker): a sum that grows
  # with the workers is the jobs slowing each other, wall time beyond
  # sum / workers is start-up and uneven shares
  job_seconds <- vapply(runs, function(r) sum(summary(r$portfolio)$buildings$seconds), numeric(1))
  print(data.frame(workers = 1:2, buildings = n, seconds = round(times),
                   buildings_per_hour = round(3600 * n / times),
                   efficiency = round(c(1, times[1] / (2 * times[2])), 2),
                   job_seconds = round(job_seconds),
                   beyond_jobs = round(times - job_seconds / 1:2)), row.names = FALSE)
}
