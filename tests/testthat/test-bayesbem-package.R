# The package's functions and S3 methods, by name: what users call.
user_functions <- function() {
  ns <- asNamespace("bayesbem")
  methods <- getNamespaceInfo(ns, "S3methods")
  names <- c(getNamespaceExports(ns), paste(methods[, 1], methods[, 2], sep = "."))
  funs <- mget(unique(names), envir = ns, ifnotfound = list(NULL))
  Filter(is.function, funs)
}

# One word per idea: an argument spelt as on the left is an idea the
# package names as on the right (CONTRIBUTING, "One word per idea").
second_spellings <- c(
  probs = "level", prob = "level", conf_level = "level", interval = "level",
  measured = "obs", holdout = "obs", observed = "obs", actual = "obs", y_obs = "obs",
  params = "parameters", pars = "parameters",
  frequency = "by", freq = "by", resolution = "by",
  n_draws = "ndraws", nsamples = "ndraws", ndraw = "ndraws", n_samples = "ndraws",
  cache = "cache_dir"
)

test_that("no function takes a second spelling of an idea", {
  found <- unlist(lapply(names(user_functions()), function(name) {
    args <- intersect(names(formals(user_functions()[[name]])), names(second_spellings))
    if (length(args) > 0L) sprintf("%s(%s): say %s", name, args, second_spellings[args])
  }))
  expect_identical(found, NULL)
})

test_that("the discrepancy choice and the number of draws are one idea each", {
  funs <- user_functions()
  defaults <- function(arg) {
    has <- Filter(function(f) arg %in% names(formals(f)), funs)
    lapply(has, function(f) formals(f)[[arg]])
  }
  # what a scenario does to the discrepancy: the same three values everywhere
  choice <- defaults("discrepancy")
  expect_setequal(names(choice), c("predict_scenario", "savings", "avoided_energy"))
  for (value in choice) expect_identical(value, quote(c("same", "proportional", "none")))
  # ndraws: all draws through the emulator, 40 where the simulator runs per
  # draw; identifiability() projects every draw's sensitivities and takes 100
  ndraws <- vapply(defaults("ndraws"), function(v) if (is.null(v)) "all" else format(v),
                   character(1))
  expect_true(all(ndraws %in% c("all", "40") | names(ndraws) == "identifiability"))
  runs <- c("predict_scenario", "savings", "avoided_energy", "validate_emulator",
            "posterior_simulate", "refine_emulator")
  expect_true(all(ndraws[runs] == "40"))
  # every interval is a level of 0.9 by default
  level <- vapply(defaults("level"), function(v) if (is.numeric(v)) v else NA_real_, numeric(1))
  expect_true(all(level[!is.na(level)] == 0.9))
})
