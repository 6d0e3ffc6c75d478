# The README's R code runs as written, in one session, on the shipped data
# (skipped where the README is not beside the tests, e.g. in R CMD check).
readme_code <- function() {
  path <- file.path("..", "..", "README.md")
  if (!file.exists(path)) skip("the README is not beside the tests")
  lines <- readLines(path, warn = FALSE)
  fences <- grep("^```", lines)
  starts <- fences[lines[fences] == "```r"]
  code <- lapply(starts, function(s) {
    end <- fences[fences > s][1]
    lines[seq(s + 1L, end - 1L)]
  })
  unlist(code)
}

test_that("the README's code blocks run", {
  skip_on_cran()
  code <- readme_code()
  expect_gt(length(code), 20)
  withr::local_options(bayesbem.progress = FALSE)
  env <- new.env()
  pdf(NULL)
  on.exit(grDevices::dev.off(), add = TRUE)
  # printed as at the console, so the print methods run too
  out <- expect_no_error(suppressWarnings(capture.output(
    source(exprs = parse(text = code), local = env, print.eval = TRUE)
  )))
  expect_true(any(grepl("Calibration parameters (physical units)", out, fixed = TRUE)))
  expect_s3_class(env$fit, "bayesbem_fit")
  expect_s3_class(env$s, "bayesbem_savings")
})
