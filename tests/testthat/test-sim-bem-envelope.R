test_that("a building's age gives the U-values of its regulations' edition", {
  standards <- bem_envelope_standards()
  expect_identical(standards$edition, c(1965L, 1976L, 1985L, 1990L, 1995L, 2002L))
  # the cited limits: 1965 walls 1.7 and roofs 1.4; 1976 walls and floors
  # 1.0, roofs 0.6; 2002 walls 0.35, roofs and floors 0.25, windows 2.2
  expect_equal(unlist(standards[1, -1]), c(u_wall = 1.7, u_roof = 1.4, u_floor = NA, u_window = NA))
  expect_equal(unlist(standards[6, -1]), c(u_wall = 0.35, u_roof = 0.25, u_floor = 0.25, u_window = 2.2))
  # a year takes the latest edition at or before it
  b1980 <- bem_building_facts(5000, floors = 4, age = 1980)
  expect_equal(unlist(b1980[c("u_wall", "u_roof", "u_floor")]), c(u_wall = 1.0, u_roof = 0.6, u_floor = 1.0))
  # what an edition does not limit stays the case study's
  expect_identical(b1980$u_window, bem_building()$u_window)
  expect_identical(bem_building_facts(5000, age = 1970)$u_floor, bem_building()$u_floor)
  b2015 <- bem_building_facts(5000, age = 2015)
  expect_equal(unlist(b2015[c("u_wall", "u_window")]), c(u_wall = 0.35, u_window = 2.2))
  # a value given wins over the age's
  expect_identical(bem_building_facts(5000, age = 1980, u_wall = 0.3)$u_wall, 0.3)
  # the geometry is the age's too: only constructions change
  plain <- bem_building_facts(5000, floors = 4)
  changed <- names(plain)[!mapply(identical, plain, b1980)]
  expect_setequal(changed, c("u_wall", "u_roof", "u_floor"))
})

test_that("an older envelope loses more heat through the embedded model", {
  weather <- system.file("extdata", "2013_AMY.epw.gz", package = "bayesbem")
  gas <- function(age) {
    sim <- bem_simulator(weather, building = bem_building_facts(2000, floors = 2, age = age),
                         output = "gas")
    sum(simulate_design(sim, data.frame(heating_setpoint = 20))$eta)
  }
  use <- vapply(c(1966, 1980, 1990, 2005), gas, numeric(1))
  expect_true(all(diff(use) < 0))
})

test_that("an age before the first limits is refused with what to give instead", {
  expect_snapshot(bem_building_facts(5000, age = 1950), error = TRUE)
  expect_error(bem_building_facts(5000, age = "1980"), class = "bayesbem_error_argument")
})
