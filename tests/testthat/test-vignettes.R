# The vignettes render from the source tree (skipped where the tests run
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

# Renders a vignette and checks it has its figures, the given passages and
# no error output.
expect_rendered <- function(name, figures, passages) {
  html <- render_vignette(name)
  images <- lengths(regmatches(html, gregexpr("<img src=\"data:image/png", html)))
  expect_gte(images, figures)
  for (passage in passages) expect_match(html, passage, fixed = TRUE)
  expect_false(grepl("## Error", html, fixed = TRUE))
}

test_that("the calibration vignette renders with its figures and comparison table", {
  skip_on_cran()
  expect_rendered("calibration", 5, c("This package and the paper", "grid likelihood"))
})

test_that("the discrepancy vignette renders, finds the hidden step, the weekend fault and the gas appliance", {
  skip_on_cran()
  expect_rendered("discrepancy", 1, c("best explained by after_change", "b predicts better",
                                      "best explained by weekend", "informed_by_gas",
                                      "gas:gamma[after_change]"))
})

test_that("the savings vignette renders its held-out check, savings and avoided energy", {
  skip_on_cran()
  expect_rendered("savings", 1, c("paired posterior draws", "fractional savings uncertainty",
                                  "held-out"))
})

test_that("the meter-data vignette renders bills on their own dates, hours of a meter and a year of them", {
  skip_on_cran()
  expect_rendered("meter-data", 0, c("beta_delta[days]", "1 hour earlier",
                                     "48 field rows", "starts before the period above it",
                                     "8760 field rows", "additive discrepancy, AR(1) noise"))
})

test_that("the smart-meter vignette renders its diagnosis, the mechanism's fit and the savings", {
  skip_on_cran()
  expect_rendered("smart-meter-fault", 0, c("best explained by", "weekend_plug_loads",
                                            "with_weekend_loads", "true_saving"))
})

test_that("the real-building vignette renders the export's check, the facts, TOWT beside and the savings", {
  skip_on_cran()
  expect_rendered("real-building", 0, c("a partial first or last reading", "typical_gas_per_m2",
                                        "GIA (m2)", "meter_load_fraction", "TOWT baseline",
                                        "a fifth less plug load"))
})

test_that("the portfolio vignette renders its refusal, total and resume", {
  skip_on_cran()
  expect_rendered("portfolio", 1, c("refused before sending", "fsu_guideline14",
                                    "already done"))
})
