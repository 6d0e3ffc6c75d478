test_that("building types carry the cited benchmarks and allowances", {
  types <- bem_building_types()
  office <- types[types$type == "office", ]
  # TM46:2008 Table 1, General office: 95 and 120 kWh/m2; 90.1-2004: 1.0 W/ft2
  expect_equal(c(office$electricity, office$fossil), c(95, 120))
  expect_equal(office$lighting, 10.8)
  expect_equal(types$electricity[types$type == "university"], 80)
  expect_true(all(types$open < types$close))
})

test_that("a type's loads start and range around its benchmark", {
  case <- bem_parameters()
  campus <- bem_parameters(type = "university")
  loads <- c("equipment_power_density", "lighting_power_density")
  others <- !case$parameter %in% loads
  expect_equal(campus[others, ], case[others, ])
  at <- match(loads, campus$parameter)
  expect_true(all(campus$min[at] < campus$initial[at] & campus$initial[at] < campus$max[at]))
  # at the initial values, lighting (in use 50 of 168 hours, a tenth of it
  # otherwise) and equipment (0.7 in use) draw the benchmark's mean power,
  # 80 kWh/m2 over 8,760 hours
  lit <- 50 / 168 + 0.1 * 118 / 168
  expect_equal(bem_building_facts(1000, type = "university")$lighting_fraction, lit)
  expect_equal(campus$initial[at[2]], 1.2 * 10.764, tolerance = 0.01)
  expect_equal(lit * campus$initial[at[2]] + 0.7 * campus$initial[at[1]], 80 / 8.76)
  expect_error(bem_parameters(type = "ofice"), "Did you mean", class = "bayesbem_error_argument")
})

test_that("a metered electricity takes the benchmark's place", {
  campus <- bem_parameters(type = "university")
  lab <- bem_parameters(type = "university", electricity = 400)
  at <- match(c("equipment_power_density", "lighting_power_density"), lab$parameter)
  lit <- bem_building_facts(1000, type = "university")$lighting_fraction
  # the lighting allowance stays the type's, the equipment draws the rest
  expect_equal(lab[at[2], c("initial", "max")], campus[at[2], c("initial", "max")])
  expect_equal(lab$min[at[2]], 0.5 * 1.2 * 10.764, tolerance = 0.01)
  # below the allowance, the lights' lower limit is half the meter's mean power
  low <- bem_parameters(type = "university", electricity = 60)
  expect_equal(low$min[at[2]], 0.5 * 60 / 8.76)
  expect_equal(low$initial[at[2]], campus$initial[at[2]])
  expect_equal(lit * lab$initial[at[2]] + 0.7 * lab$initial[at[1]], 400 / 8.76)
  expect_equal(lab$max[at[1]], 1.5 * 400 / 8.76 / 0.7)
  expect_equal(bem_parameters(type = "university", electricity = 80), campus)
  expect_error(bem_parameters(electricity = 400), "needs a", class = "bayesbem_error_argument")
  expect_error(bem_parameters(type = "office", electricity = "400"), "positive number",
               class = "bayesbem_error_argument")
})

test_that("a type's prior spans its benchmark's electricity", {
  # a ventilation-only fan (1 l/s per m2), as in most uncooled campuses
  area <- 5000
  building <- bem_building_facts(area, floors = 3, type = "university", cooling = FALSE,
                                 fan_flow = 1e-3 * area)
  pars <- bem_parameters(type = "university")
  sim <- bem_simulator(epw_monthly(shipped_epw(2013)), parameters = pars, building = building)
  pars <- pars[pars$parameter %in% c("equipment_power_density", "lighting_power_density"), ]
  runs <- simulate_design(sim, design_lhs(pars, 20, seed = 1))
  annual <- tapply(runs$eta, rep(1:20, each = 12), sum) / area
  expect_lt(min(annual), 80)
  expect_gt(max(annual), 80)
})

test_that("a type's opening hours make the occupancy unless it is given", {
  retail <- bem_building_facts(3000, type = "retail")
  week <- matrix(retail$occupancy, 24)
  expect_equal(colSums(week), c(rep(9, 6), 0))
  expect_equal(which(week[, 1] == 1) - 1, 9:17)
  own <- rep(0.5, 168)
  expect_equal(bem_building_facts(3000, type = "retail", occupancy = own)$occupancy, own)
  expect_equal(sum(bem_building_facts(3000, type = "hospital")$occupancy), 168)
})
