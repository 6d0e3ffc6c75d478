# Synthetic calibration problems with a known truth and a hidden effect, for
# the discrepancy tests: the embedded model on 48 months of weather (2012,
# 2013, and the same two years perturbed), two calibration parameters, a
# 30-run Latin hypercube over all months (as in the paper; with 10 runs the
# emulator's error pulls tf towards the design points and biases it by more
# than the hidden effects do), twelve months' measurements held
# out (one per calendar month in each two-year block). Each case is fitted
# once per test run.
synthetic_truth <- list(equipment_power_density = 15, infiltration_per_exterior_area = 0.0008)

synthetic_held_out <- c(2, 7, 11, 16, 21, 24, 26, 31, 35, 40, 45, 48)

synthetic_simulator <- function() {
  years <- rbind(epw_monthly(shipped_epw(2012)), epw_monthly(shipped_epw(2013)))
  perturbed <- withr::with_seed(7, within(years, {
    temp <- temp + stats::rnorm(24, sd = 1.5)
    rh <- rh + stats::rnorm(24, sd = 4)
    dni <- dni * stats::runif(24, 0.9, 1.1)
  }))
  bem_simulator(rbind(years, perturbed))
}

# Candidates the simulator does not use: the external covariate and the
# step of the hidden effects, and decoys correlated with the inputs.
synthetic_covariates <- function(sim) {
  withr::with_seed(99, data.frame(
    occupancy = round(stats::runif(48), 2),
    after_change = rep(0:1, c(14, 34)),
    decoy_temp = sim$x$temp + stats::rnorm(48, sd = 3),
    decoy_rh = sim$x$rh + stats::rnorm(48, sd = 5)
  ))
}

synthetic_effects <- list(
  none = NULL,
  input = function(d) 250 * (d$rh > 47),       # dehumidification the simulator lacks
  covariate = function(d) 250 * d$occupancy,    # events the simulator does not know
  step = function(d) 200 * d$after_change,      # equipment added in month 15
  # events that cost energy only in the cooling season
  interaction = function(d) 300 * d$occupancy * (d$temp > 15)
)

synthetic_case <- local({
  cache <- list()
  function(kind) {
    if (is.null(cache[[kind]])) cache[[kind]] <<- make_synthetic_case(kind)
    cache[[kind]]
  }
})

make_synthetic_case <- function(kind, noise_seed = 5) {
  sim <- synthetic_simulator()
  covariates <- synthetic_covariates(sim)
  field <- simulate_field(sim, synthetic_truth, covariates = covariates,
                          effect = synthetic_effects[[kind]], noise_sd = 15, seed = noise_seed)
  params <- sim$parameters[sim$parameters$parameter %in% names(synthetic_truth), ]
  design <- design_lhs(params, n = 30, seed = 1)
  runs <- simulate_design(sim, design)
  held_out <- synthetic_held_out
  # the runs cover the held-out months too (the simulator can be run
  # anywhere; only measurements are held out), so the design is a grid
  base <- suppressWarnings(
    calibrate(field[-held_out, c("y", "temp", "rh", "solar")], runs, chains = 2, iter = 600,
              seed = test_seed(11), cores = 2, control = list(adapt_delta = 0.9), refresh = 0),
    classes = "bayesbem_warning_convergence"
  )
  # the modeller's physical reading of a humidity cause: humid months
  humid <- data.frame(humid = as.numeric(field$rh > 47))
  list(field = field, train_covariates = covariates[-held_out, ],
       extension_covariates = cbind(covariates, humid)[-held_out, ],
       holdout = cbind(field, humid)[held_out, ], base = base)
}

# The case's base fit extended with `with`, once per test run.
synthetic_extension <- local({
  cache <- list()
  function(kind, with) {
    key <- paste(kind, with)
    if (is.null(cache[[key]])) {
      case <- synthetic_case(kind)
      cache[[key]] <<- suppressWarnings(
        extend(case$base, with = with, covariates = case$extension_covariates, refresh = 0),
        classes = "bayesbem_warning_convergence"
      )
    }
    cache[[key]]
  }
})
