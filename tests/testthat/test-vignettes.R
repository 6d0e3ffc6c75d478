# Both vignettes render from the source tree (skipped where the tests run
# without it, e.g. in R CMD check, which builds the vignettes itself).
vignette_source <- function(name) {
  path <- file.path("..", "..", "vignettes", paste0(name, ".Rmd"))
  if (!file.exists(path)) skip("vignette sources are not beside the tests")
  skip_if_not(rmarkdown::pandoc_available(), "pandoc is not available")
  normalizePath(path)
}

render_vignette <- function(name) {
  out <- withr::local_tempdir()
  html <- rmarkdown::render(vignette_source(name), output_dir = out, intermediates_dir = out,
                            envir = new.env(), quiet = TRUE)
  paste(readLines(html, warn = FALSE), collapse = "\n")
}

count <- function(pattern, text) lengths(regmatches(text, gregexpr(pattern, text)))

test_that("the calibration vignette renders with its figures and comparison table", {
  skip_on_cran()
  html <- render_vignette("calibration")
  expect_gte(count("<img src=\"data:image/png", html), 5)
  expect_match(html, "This package and the paper")
  expect_match(html, "grid likelihood")
  expect_false(grepl("## Error", html, fixed = TRUE))
})

test_that("the discrepancy vignette renders and finds the hidden step", {
  skip_on_cran()
  html <- render_vignette("discrepancy")
  expect_gte(count("<img src=\"data:image/png", html), 1)
  expect_match(html, "best explained by after_change")
  expect_match(html, "b predicts better")
  expect_false(grepl("## Error", html, fixed = TRUE))
})
