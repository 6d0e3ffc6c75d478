# Three small buildings: the embedded model's bills at two truths and one
# building whose bills the runs cannot reach; savings of equipment x 0.7.
portfolio_buildings <- function() {
  sim <- bem_simulator(shipped_epw(2013))
  pars <- sim$parameters[sim$parameters$parameter == "equipment_power_density", ]
  runs <- simulate_design(sim, design_lhs(pars, 8, seed = 1))
  bills <- function(density, seed) {
    simulate_field(sim, list(equipment_power_density = density), noise_sd = 20, seed = seed)
  }
  buildings <- data.frame(id = c("b1", "b2", "b3"))
  buildings$field <- list(bills(10, 1), bills(20, 2), bills(10, 3))
  buildings$field[[3]]$y <- 10 * buildings$field[[3]]$y
  buildings$runs <- list(runs, runs, runs)
  buildings$simulator <- list(sim, sim, sim)
  buildings
}

lighter_equipment <- function(s) scenario(s, scale = c(equipment_power_density = 0.7))

run_portfolio <- function(buildings, dir, ...) {
  suppressMessages(calibrate_portfolio(buildings, dir, retrofit = lighter_equipment, ndraws = 10,
                                       seed = test_seed(70), chains = 2, iter = 600, cores = 1,
                                       ...))
}

test_that("a portfolio calibrates each building, refuses what cannot run, and resumes", {
  skip_on_cran()
  dir <- withr::local_tempdir()
  buildings <- portfolio_buildings()
  p <- run_portfolio(buildings, dir)
  status <- vapply(p$records, `[[`, "", "status")
  expect_equal(unname(status), c("done", "done", "refused"))
  expect_equal(p$records$b3$error_class, "bayesbem_error_prior_misses")
  expect_setequal(list.files(dir), paste0(c("b1", "b2", "b3"), ".rds"))
  # each building's own truth: the posterior of the lighter one lies lower
  expect_lt(mean(p$records$b1$savings_draws), mean(p$records$b2$savings_draws))
  expect_true(all(p$records$b1$savings_draws > 0))
  # a second call sends only what is not done: a deleted result (a job
  # killed before it wrote) and the refused building again
  unlink(file.path(dir, "b2.rds"))
  kept <- file.info(file.path(dir, "b1.rds"))$mtime
  expect_message(again <- calibrate_portfolio(buildings, dir, retrofit = lighter_equipment,
                                              ndraws = 10, seed = test_seed(70), chains = 2,
                                              iter = 600, cores = 1),
                 "0 of 3 buildings to calibrate|1 of 3 buildings to calibrate; 1 already done",
                 class = "bayesbem_message_portfolio")
  expect_equal(file.info(file.path(dir, "b1.rds"))$mtime, kept)
  expect_equal(again$records$b2$savings_draws, p$records$b2$savings_draws)
})

test_that("a failing building is recorded with its error and the others complete", {
  skip_on_cran()
  dir <- withr::local_tempdir()
  buildings <- portfolio_buildings()[1:2, ]
  buildings$runs[2] <- list(NULL)
  buildings$design <- list(NULL, data.frame(no_such_parameter = 1:3))
  p <- run_portfolio(buildings, dir)
  expect_equal(p$records$b1$status, "done")
  expect_equal(p$records$b2$status, "failed")
  expect_match(p$records$b2$error, "no_such_parameter")
  expect_match(p$records$b2$error_class, "^bayesbem_error")
})

# The two first buildings' results under a future plan, each plan's once
# (the tests below compare them).
plan_results <- local({
  done <- list()
  function(plan) {
    if (is.null(done[[plan]])) {
      strategy <- switch(plan, sequential = future::sequential,
                         multisession = future::tweak(future::multisession, workers = 2),
                         batchtools = future.batchtools::batchtools_local,
                         slurm = future.batchtools::batchtools_slurm)
      # batchtools' registries in a temporary folder, not the working directory
      withr::local_options(future.cache.path = withr::local_tempdir())
      old <- future::plan(strategy)
      on.exit(future::plan(old), add = TRUE)
      p <- run_portfolio(portfolio_buildings()[1:2, ], withr::local_tempdir())
      done[[plan]] <<- lapply(p$records, function(r) r[c("status", "rhat", "cvrmse", "savings_draws")])
    }
    done[[plan]]
  }
})

# A Slurm cluster that takes jobs here (CI starts one node with
# tools/slurm-one-node.sh), or the reason there is none.
slurm_missing <- function() {
  if (Sys.which("sbatch") == "") return("Slurm is not installed (tools/slurm-one-node.sh starts one node)")
  state <- suppressWarnings(system2("sinfo", c("-h", "-o", "%t"), stdout = TRUE, stderr = TRUE))
  if (!any(state %in% c("idle", "mix", "alloc"))) {
    return(paste0("no Slurm node takes jobs (sinfo: ", paste(state, collapse = " "), ")"))
  }
  # a node that is up but does not run jobs would hang the test: one job first
  ran <- suppressWarnings(system2("timeout", c("60", "srun", "-t", "1", "true"), stdout = FALSE, stderr = FALSE))
  if (ran != 0) return("Slurm did not run a one-second job within a minute (srun true)")
  NULL
}

test_that("a portfolio gives the same results under sequential, multisession and batchtools plans", {
  skip_on_cran()
  skip_if_not_installed("future.batchtools")
  expect_equal(plan_results("multisession"), plan_results("sequential"))
  expect_equal(plan_results("batchtools"), plan_results("sequential"))
})

test_that("a portfolio sent to a Slurm cluster gives the same results as on one process", {
  skip_on_cran()
  skip_if_not_installed("future.batchtools")
  missing <- slurm_missing()
  skip_if(!is.null(missing), missing)
  # batchtools asks squeue for the jobs of $USER, which a container's root
  # shell may not set (the jobs then look lost as soon as they are queued)
  if (!nzchar(Sys.getenv("USER"))) withr::local_envvar(USER = Sys.info()[["user"]])
  expect_equal(plan_results("slurm"), plan_results("sequential"))
})

test_that("a killed portfolio resumes without redoing finished buildings", {
  skip_on_cran()
  skip_if_not_installed("callr")
  dir <- withr::local_tempdir()
  buildings <- portfolio_buildings()[c(1, 2, 1), ]
  buildings$id <- c("b1", "b2", "b4")
  table <- file.path(dir, "buildings.rds")
  saveRDS(buildings, table)
  results <- file.path(dir, "results")
  job <- callr::r_bg(function(table, results, lib) {
    .libPaths(lib)
    options(bayesbem.progress = FALSE)
    bayesbem::calibrate_portfolio(readRDS(table), results, chains = 2, iter = 600, cores = 1,
                                  seed = 70)
  }, list(table, results, .libPaths()))
  on.exit(job$kill(), add = TRUE)
  waited <- 0
  while (length(list.files(results, "[.]rds$")) == 0L && waited < 300 && job$is_alive()) {
    Sys.sleep(0.5)
    waited <- waited + 0.5
  }
  job$kill()
  finished <- list.files(results, "[.]rds$")
  expect_gte(length(finished), 1L)
  skip_if(length(finished) == 3L, "the portfolio finished before it could be killed")
  times <- file.info(file.path(results, finished))$mtime
  expect_message(p <- suppressWarnings(calibrate_portfolio(buildings, results, chains = 2,
                                                           iter = 600, cores = 1, seed = 70)),
                 sprintf("%d of 3 buildings? to calibrate; %d already done",
                         3L - length(finished), length(finished)),
                 class = "bayesbem_message_portfolio")
  expect_equal(file.info(file.path(results, finished))$mtime, times)
  expect_true(all(vapply(p$records, `[[`, "", "status") == "done"))
})

test_that("a portfolio's table is checked before anything runs", {
  dir <- withr::local_tempdir()
  buildings <- data.frame(id = c("a", "a"))
  buildings$field <- list(seb_field, seb_field)
  buildings$runs <- list(seb_sim, seb_sim)
  expect_snapshot(calibrate_portfolio(buildings, dir), error = TRUE)
  buildings$id <- c("a", "b")
  expect_snapshot(calibrate_portfolio(buildings, dir, retrofit = lighter_equipment), error = TRUE)
  expect_error(calibrate_portfolio(buildings[c("id", "field")], dir),
               class = "bayesbem_error_argument")
  expect_error(calibrate_portfolio(buildings, 3), class = "bayesbem_error_argument")
  blocker <- file.path(dir, "a-file")
  writeLines("", blocker)
  expect_error(calibrate_portfolio(buildings, file.path(blocker, "results")),
               "could not be created", class = "bayesbem_error_argument")
  # what the portfolio sets itself is not calibrate()'s to take
  expect_snapshot(calibrate_portfolio(buildings, dir, progress = TRUE), error = TRUE)
  # one output per building: a meter of several is refused, not read in part
  buildings$field[[2]] <- rbind(cbind(seb_field, output = "elec"), cbind(seb_field, output = "gas"))
  expect_snapshot(calibrate_portfolio(buildings, dir), error = TRUE)
  meters <- withr::with_seed(1, random_outputs_data())
  buildings$field[[2]] <- koh_data(meters$field, meters$sim)
  expect_error(calibrate_portfolio(buildings, dir), "one output", class = "bayesbem_error_argument")
  expect_identical(list.files(dir, pattern = "rds$"), character(0))
})
