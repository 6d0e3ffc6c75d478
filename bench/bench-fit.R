# Benchmark: the package's KOH program (koh.stan, its grid and dense
# likelihoods) against a naive element-wise program written like the paper's
# listing, on the shipped case study, in the same run.
# Times compilation, warm-up and sampling, and the minimum bulk ESS per second
# over tf and the GP hyperparameters. One chain of 500 iterations (250 warm-up)
# per seed, as the issue asks; several seeds because one chain's ESS is noisy.
# Usage, from the package root, with bayesbem installed:
#   Rscript bench/bench-fit.R [seeds]
suppressPackageStartupMessages(library(bayesbem))
args <- commandArgs(trailingOnly = TRUE)
seeds <- if (length(args) > 0) seq_len(as.integer(args[1])) else 1:3
rstan::rstan_options(auto_write = FALSE)
# Debian's r-cran-bh ships no headers; Boost is in /usr/include there
if (!nzchar(system.file("include", "boost", package = "BH"))) {
  rstan::rstan_options(boost_lib = "/usr/include")
}

d <- koh_data(seb_field, seb_sim)
stan_data <- list(grid = bayesbem:::koh_stan_data(d, koh_priors(), structure = "grid"),
                  dense = bayesbem:::koh_stan_data(d, koh_priors(), structure = "dense"))
# the naive program reads the dense likelihood's simulation rows as m and eta
stan_data$naive <- utils::modifyList(stan_data$dense, list(m = stan_data$dense$mt,
                                                           eta = stan_data$dense$eta_c))
include_dir <- system.file("stan", package = "bayesbem")

compile <- function(file) {
  t <- system.time(model <- rstan::stan_model(file, isystem = include_dir))[["elapsed"]]
  list(model = model, compile = t)
}
koh <- compile(file.path(include_dir, "koh.stan"))
programs <- list(grid = koh, dense = koh, naive = compile("bench/naive_koh.stan"))

min_ess_per_s <- function(fit) {
  draws <- posterior::as_draws_array(as.array(fit, pars = c("tf", "beta_eta", "beta_delta",
                                                            "lambda_eta", "lambda_delta",
                                                            "lambda_e")))
  ess <- posterior::summarise_draws(draws, posterior::ess_bulk)$`posterior::ess_bulk`
  times <- rstan::get_elapsed_time(fit)
  c(warmup = times[, "warmup"], sampling = times[, "sample"], min_ess = min(ess),
    min_ess_per_s = min(ess) / times[, "sample"],
    min_ess_per_s_total = min(ess) / sum(times))
}

rows <- list()
for (name in names(programs)) {
  for (seed in seeds) {
    fit <- rstan::sampling(programs[[name]]$model, data = stan_data[[name]], chains = 1, iter = 500,
                           seed = seed, refresh = 0, control = list(adapt_delta = 0.9))
    rows[[length(rows) + 1]] <- data.frame(program = name, seed = seed,
                                           compile_s = programs[[name]]$compile,
                                           t(min_ess_per_s(fit)))
  }
}
res <- do.call(rbind, rows)
cat("\nPer run (1 chain x 500 iterations, adapt_delta = 0.9):\n")
print(res, digits = 3, row.names = FALSE)
agg <- aggregate(cbind(warmup, sampling, min_ess, min_ess_per_s, min_ess_per_s_total) ~ program,
                 data = res, FUN = mean)
cat("\nMean over seeds:\n")
print(agg, digits = 3, row.names = FALSE)
naive <- agg$min_ess_per_s[agg$program == "naive"]
for (name in c("grid", "dense")) {
  cat(sprintf("\nmin bulk-ESS/s, %s / naive: %.1fx (targets: >= 10x, issue 3; grid >= 50x, issue 7)",
              name, agg$min_ess_per_s[agg$program == name] / naive))
}
cat("\n")
cat(sprintf("machine: %s, %d cores; R %s; rstan %s; %s\n", Sys.info()[["nodename"]],
            parallel::detectCores(), getRversion(), packageVersion("rstan"), Sys.Date()))
