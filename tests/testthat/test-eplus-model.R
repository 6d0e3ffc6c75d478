test_that("a model is read by EnergyPlus's converter and edited by class, name and field", {
  skip_if_no_eplus()
  model <- seb_model()
  expect_s3_class(model, "bayesbem_eplus_model")
  expect_equal(model$version, "25.2")
  expect_equal(eplus_get(model, "Lights", "AllLights", "Watts per Floor Area"), 14.6)
  expect_equal(eplus_get(model, "Lights", "AllLights", "watts_per_floor_area"), 14.6)
  # an extensible field by its number
  expect_equal(eplus_get(model, "Schedule:Day:Interval", "All Weekdays 1", "Value Until Time 3"), 0.5)
  edited <- eplus_set(model, "Schedule:Day:Interval", "All Weekdays 1", `Value Until Time 3` = 0.6,
                      `Interpolate to Timestep` = "Average")
  expect_equal(eplus_get(edited, "Schedule:Day:Interval", "All Weekdays 1", "Value Until Time 3"), 0.6)
  expect_equal(eplus_get(edited, "Schedule:Day:Interval", "All Weekdays 1", "Value Until Time 2"), 0.3)
  expect_equal(eplus_objects(model, "Output:Meter"), c("Output:Meter 1", "Output:Meter 2"))
  added <- eplus_add(model, "Output:Meter", key_name = "InteriorLights:Electricity",
                     reporting_frequency = "Hourly")
  expect_equal(eplus_objects(added, "Output:Meter")[3], "Output:Meter 3")
  # saved as IDF and as epJSON, and read back
  for (ext in c(".idf", ".epJSON")) {
    path <- withr::local_tempfile(fileext = ext)
    eplus_save(edited, path)
    back <- eplus_model(path)
    expect_equal(eplus_get(back, "Schedule:Day:Interval", "All Weekdays 1", "Value Until Time 3"), 0.6)
    expect_equal(back$json, edited$json, ignore_attr = TRUE)
  }
})

test_that("unknown classes, objects and fields are classed errors", {
  skip_if_no_eplus()
  model <- seb_model()
  expect_snapshot(eplus_get(model, "Light", "AllLights", "Watts per Floor Area"), error = TRUE)
  expect_snapshot(eplus_set(model, "Lights", "All Lights", `Watts per Floor Area` = 3), error = TRUE)
  expect_error(eplus_get(model, "Schedule:Day:Interval", "All Weekdays 1", "Value Until Time 9"),
               class = "bayesbem_error_eplus_model")
  expect_error(eplus_set(model, "Lights", "AllLights", 3), class = "bayesbem_error_argument")
  expect_error(eplus_add(model, "Lights", "AllLights"), class = "bayesbem_error_eplus_model")
  expect_error(eplus_get(list(), "Lights", "AllLights", "x"), class = "bayesbem_error_argument")
})

test_that("a model of another EnergyPlus version names both versions and the way to transition", {
  path <- example_model_path("seb_8_7.idf")
  expect_error(eplus_model(path), class = "bayesbem_error_eplus_version")
  expect_snapshot(eplus_model(path), error = TRUE)
  newer <- withr::local_tempfile(fileext = ".idf")
  writeLines(sub("25\\.2", "26.1", readLines(example_model_path("1ZoneUncontrolled_25_2.idf"))), newer)
  expect_error(eplus_model(newer), class = "bayesbem_error_eplus_version")
  expect_error(eplus_model("no-such-model.idf"), class = "bayesbem_error_file")
})

test_that("relative file names are resolved from the model's folder", {
  skip_if_no_eplus()
  folder <- withr::local_tempdir()
  writeLines(as.character(rep(1, 8760)), file.path(folder, "on.csv"))
  model <- eplus_add(seb_model(), "Schedule:File", "Always On File",
                     file_name = "on.csv", column_number = 1, rows_to_skip_at_top = 0)
  eplus_save(model, file.path(folder, "model.epJSON"))
  back <- eplus_model(file.path(folder, "model.epJSON"))
  expect_equal(eplus_get(back, "Schedule:File", "Always On File", "File Name"),
               normalizePath(file.path(folder, "on.csv")))
})

test_that("a file's conversion is kept for the session, keyed on its contents", {
  skip_if_no_eplus()
  dir <- eplus_path()
  model <- seb_model()
  path <- withr::local_tempfile(fileext = ".epJSON")
  write_epjson(model$json, path)
  first <- convert_model(path, dir, "idf")
  # the same contents at another path: the file converted before
  copy <- withr::local_tempfile(fileext = ".epJSON")
  file.copy(path, copy)
  expect_identical(convert_model(copy, dir, "idf"), first)
  # other contents are converted afresh, and so is a kept file since removed
  write_epjson(eplus_set(model, "Lights", "AllLights", `Watts per Floor Area` = 9)$json, copy)
  other <- convert_model(copy, dir, "idf")
  expect_false(identical(other, first))
  expect_false(identical(readLines(other), readLines(first)))
  unlink(first)
  again <- convert_model(path, dir, "idf")
  expect_false(identical(again, first))
  expect_true(file.exists(again))
})
