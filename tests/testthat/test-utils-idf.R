test_that("an IDF survives reading and writing", {
  model <- bayesbem:::read_idf(system.file("extdata", "seb_25_2.idf.gz", package = "bayesbem"))
  path <- withr::local_tempfile(fileext = ".idf")
  bayesbem:::write_idf(model, path)
  expect_identical(bayesbem:::read_idf(path), model)
  classes <- vapply(model, `[`, character(1), 1)
  expect_equal(model[[which(classes == "Version")]][2], "25.2")
  expect_equal(sum(classes == "Material"), 13)
})

test_that("map rows set values, multiply or divide the original", {
  model <- list(c("Version", "25.2"), c("Material", "Stuco", "Smooth", "0.01", "0.7", "1800"),
                c("Lights", "AllLights", "Zone", "Sched", "Watts/Area", "", "10"))
  map <- data.frame(parameter = c("wall_R", "wall_rho", "lpd"), apply = c("divide", "multiply", "value"),
                    object = c(2, 2, 3), position = c(5, 6, 7), original = c(0.7, 1800, 10))
  out <- bayesbem:::set_idf_fields(model, map, list(wall_R = 1.1, wall_rho = 0.98, lpd = 12.5,
                                                    unmapped = 3))
  expect_equal(as.numeric(out[[2]][5]), 0.7 / 1.1, tolerance = 1e-14)
  expect_equal(as.numeric(out[[2]][6]), 1800 * 0.98)
  expect_equal(out[[3]][7], "12.5")
  expect_identical(out[[1]], model[[1]])
})

test_that("the shipped parameter map covers the study's 14 parameters", {
  map <- eplus_parameter_map()
  expect_setequal(unique(map$parameter), bem_parameters()$parameter)
  expect_equal(unique(map$apply[grepl("_R_multiplier$", map$parameter)]), "divide")
  expect_equal(unique(map$apply[grepl("_density_multiplier$", map$parameter)]), "multiply")
  table <- bayesbem:::map_parameters(map)
  expect_equal(nrow(table), 14)
})
