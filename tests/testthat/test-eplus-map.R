test_that("a map row with a wildcard sets every object it matches, and says which", {
  skip_if_no_eplus()
  model <- seb_model()
  row <- function(name) {
    data.frame(parameter = "gypsum_R_multiplier", object_type = "Material",
               object_name = name, field = "Conductivity", apply = "divide", initial = 1,
               min = 0.9, max = 1.1)
  }
  gypsum <- c("Gypsum Board - 3/4 in.", "Gypsum Board - 5/8 in.")
  expect_message(wild <- bayesbem:::check_parameter_map(row("Gypsum Board*"), model),
                 "matched 2 objects", class = "bayesbem_message_map_rows")
  explicit <- bayesbem:::check_parameter_map(do.call(rbind, lapply(gypsum, row)), model)
  expect_equal(wild, explicit)
  # "*": every object of the class
  all <- suppressMessages(bayesbem:::check_parameter_map(row("*"), model))
  expect_setequal(all$object_name, eplus_objects(model, "Material"))
  # the runs see it: both boards' conductivity divided
  edited <- bayesbem:::apply_parameters(model, wild, list(), list(gypsum_R_multiplier = 2))
  for (board in gypsum) {
    expect_equal(eplus_get(edited, "Material", board, "Conductivity"),
                 eplus_get(model, "Material", board, "Conductivity") / 2)
  }
  expect_error(bayesbem:::check_parameter_map(row("Brick*"), model),
               class = "bayesbem_error_parameters")
})
