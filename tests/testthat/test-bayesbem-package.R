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
  # a verb's methods for one and for several outputs take its defaults
  verb_of <- function(names) sub("\\.bayesbem_fit(_outputs)?$", "", names)
  expect_setequal(unique(verb_of(names(choice))), c("predict_scenario", "savings", "avoided_energy"))
  for (value in choice) expect_identical(value, quote(c("same", "proportional", "none")))
  # ndraws: all draws through the emulator, 40 where the simulator runs per
  # draw; identifiability() projects every draw's sensitivities and takes 100
  ndraws <- vapply(defaults("ndraws"), function(v) if (is.null(v)) "all" else format(v),
                   character(1))
  expect_true(all(ndraws %in% c("all", "40") | verb_of(names(ndraws)) == "identifiability"))
  runs <- c("predict_scenario", "savings", "avoided_energy", "validate_emulator",
            "posterior_simulate", "refine_emulator")
  expect_true(all(ndraws[runs] == "40"))
  # `level` is an interval's, 0.9 by default, and nothing else
  level <- vapply(defaults("level"), function(v) if (is.numeric(v)) v else NA_real_, numeric(1))
  expect_equal(level[level != 0.9 | is.na(level)], stats::setNames(numeric(0), character(0)))
})

# The package's layers in CONTRIBUTING's table of the workflow, in order:
# each row's layer (its first column) and its R files, in order; the
# first row is the shared layer. Skipped where the tests run without the
# sources beside them (R CMD check).
workflow_files <- function() {
  contributing <- file.path("..", "..", "CONTRIBUTING.md")
  if (!file.exists(contributing) || !dir.exists(file.path("..", "..", "R"))) {
    skip("the package sources are not beside the tests")
  }
  rows <- grep("^\\| [A-Za-z]", readLines(contributing), value = TRUE)
  rows <- rows[grepl("`R/", rows, fixed = TRUE)]
  files <- lapply(rows, function(row) {
    m <- regmatches(row, gregexpr("`R/[^`]+\\.R`", row))[[1]]
    gsub("`|R/", "", m)
  })
  layers <- sub("^\\| ([a-z]+) \\|.*", "\\1", rows)
  list(order = unlist(files), shared = files[[1]],
       layer = stats::setNames(rep(layers, lengths(files)), unlist(files)), layers = layers)
}

# The functions each R file defines and the names its code uses (free
# names of its functions; every name of its other top-level code).
file_names <- function(path) {
  defined <- character()
  used <- character()
  for (e in parse(path, keep.source = FALSE)) {
    if (is.call(e) && identical(e[[1]], as.name("<-")) && is.name(e[[2]])) {
      defined <- c(defined, as.character(e[[2]]))
      value <- e[[3]]
      used <- c(used, if (is.call(value) && identical(value[[1]], as.name("function"))) {
        codetools::findGlobals(eval(value, baseenv()))
      } else {
        all.names(value)
      })
    } else {
      used <- c(used, all.names(e))
    }
  }
  list(defined = defined, used = unique(used))
}

test_that("every R file is named by its layer and uses only layers above it", {
  flow <- workflow_files()
  files <- basename(list.files(file.path("..", "..", "R"), pattern = "\\.R$"))
  expect_setequal(flow$order, files)
  # a file's name starts with its layer, but for the shared layer's two
  # files that rstantools and roxygen name
  prefix <- sub("^([a-z]+)([-.].*)$", "\\1", flow$order)
  conventional <- c("stanmodels.R", "bayesbem-package.R")
  misnamed <- flow$order[prefix != flow$layer[flow$order] & !flow$order %in% conventional]
  expect_identical(misnamed, character(0))
  names <- lapply(stats::setNames(file.path("..", "..", "R", flow$order), flow$order), file_names)
  owner <- unlist(lapply(flow$order, function(f) {
    stats::setNames(rep(f, length(names[[f]]$defined)), names[[f]]$defined)
  }))
  rank <- match(flow$layer, flow$layers)
  names(rank) <- names(flow$layer)
  wrong <- unlist(lapply(flow$order, function(f) {
    used <- intersect(names[[f]]$used, names(owner))
    from <- owner[used]
    shared <- from %in% flow$shared
    above <- rank[from] > rank[f] & !shared
    later <- rank[from] == rank[f] & match(from, flow$order) > match(f, flow$order) & !shared
    unshared <- f %in% flow$shared & !shared
    bad <- from[above | later | unshared]
    if (length(bad) > 0L) {
      sprintf("%s (%s) uses %s() of %s (%s)", f, flow$layer[f], names(bad), bad, flow$layer[bad])
    }
  }))
  expect_identical(wrong, NULL)
})
