initial_params <- function() {
  stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
}

test_that("without gains, the heating need is transmission plus ventilation loss", {
  b <- bem_building(window_fraction = 0, occupant_gain = 0, fan_flow = 0)
  p <- initial_params()
  p$lighting_power_density <- 0
  p$equipment_power_density <- 0
  weather <- data.frame(hours = c(744, 720), temp = c(-5, 30), dni = 0, dhi = 0, ghi = 0)
  out <- bem_monthly(p, weather, b)
  # by hand: H_tr = 0.5 * 106.8 + 0.2 * 79 + 0 + 0.5 * 0.4 * 79 = 84.99 W/K,
  # H_ve = 1206 * (0.001524 * (106.8 + 79) + 0.03) = 377.6578... W/K
  h <- 0.5 * 106.8 + 0.2 * 79 + 0.5 * 0.4 * 79 + 1206 * (0.001524 * 185.8 + 0.03)
  expect_equal(out$heating_need[1], h * (18.3 - -5) * 744 / 1000)
  expect_equal(out$heating_need[2], 0)
  expect_equal(out$cooling_need[1], 0)
  # the baseboard meets 15 % of the need up to its capacity (1.5 kW x 744 h
  # binds at -5 C); gas meets the rest at the burner efficiency
  expect_equal(out$electricity[1], 1.5 * 744)
  expect_equal(out$gas[1], (out$heating_need[1] - 1.5 * 744) / 0.95)
  mild <- bem_monthly(p, data.frame(hours = 744, temp = 10, dni = 0, dhi = 0, ghi = 0), b)
  expect_equal(mild$electricity, 0.15 * mild$heating_need)
  expect_equal(mild$gas, 0.85 * mild$heating_need / 0.95)
})

test_that("R-value multipliers scale the conductances", {
  b <- bem_building(window_fraction = 0, occupant_gain = 0, fan_flow = 0)
  p <- initial_params()
  p$lighting_power_density <- 0
  p$equipment_power_density <- 0
  p$infiltration_per_exterior_area <- 0
  p$wall_R_multiplier <- 1.1
  weather <- data.frame(hours = 24, temp = 8.3, dni = 0, dhi = 0, ghi = 0)
  h <- 0.5 / 1.1 * 106.8 + 0.2 * 79 + 0.5 * 0.4 * 79 + 1206 * 0.03
  expect_equal(bem_monthly(p, weather, b)$heating_need, h * 10 * 24 / 1000)
})

test_that("utilisation factors follow ISO 13790", {
  a <- 2
  expect_equal(bayesbem:::gain_utilisation(0.5, a), (1 - 0.5^2) / (1 - 0.5^3))
  expect_equal(bayesbem:::gain_utilisation(1, a), 2 / 3)
  expect_equal(bayesbem:::loss_utilisation(2, a), (1 - 2^-2) / (1 - 2^-3))
  expect_equal(bayesbem:::loss_utilisation(-1, a), 1)
})

test_that("the model responds to its parameters as physics says", {
  w <- epw_monthly(shipped_epw(2013))
  p <- initial_params()
  base <- bem_monthly(p, w)
  expect_true(all(base$electricity > 0))
  expect_gt(sum(base$cooling_need[6:8]), 0)
  expect_gt(sum(base$heating_need[c(1, 12)]), sum(base$heating_need[6:8]))
  more <- utils::modifyList(p, list(equipment_power_density = 25))
  expect_true(all(bem_monthly(more, w)$electricity > base$electricity))
  efficient_fan <- utils::modifyList(p, list(fan_total_efficiency = 0.8))
  expect_true(all(bem_monthly(efficient_fan, w)$electricity < base$electricity))
  better_cop <- utils::modifyList(p, list(dx_cooling_cop = 5))
  elec <- bem_monthly(better_cop, w)$electricity
  expect_lt(elec[7], base$electricity[7])
  expect_equal(elec[1], base$electricity[1])
})

test_that("unknown building properties are rejected", {
  expect_error(bem_building(floor = 10), class = "bayesbem_error_argument")
})

test_that("a building described by its facts scales the case study's", {
  # the case study's own facts give the case study's building
  # (4 sqrt(79) 3 m of wall is 106.7 m2, the case study's 106.8)
  expect_equal(bem_building_facts(79), bem_building(), tolerance = 2e-3)
  big <- bem_building_facts(6000, floors = 4, roof_area = 1600, clock = "Europe/London")
  expect_equal(big$wall_area, 4 * sqrt(1500) * 3 * 4)
  expect_equal(big$roof_area, 1600)
  expect_equal(big$fan_flow / big$floor_area, bem_building()$fan_flow / 79)
  expect_equal(big$floor_loss_factor * big$floor_area, bem_building()$floor_loss_factor * 1500)
  expect_equal(big$clock, "Europe/London")
  # per m2 of floor, a building 76 times the case study's uses a little
  # less: less facade per m2, and the baseboard's capacity is the case study's
  p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  w <- epw_monthly(shipped_epw(2013))
  small <- sum(bem_monthly(p, w)$electricity) / 79
  large <- sum(bem_monthly(p, w, bem_building_facts(6000))$electricity) / 6000
  expect_lt(large, small)
  expect_gt(large, 0.8 * small)
  expect_error(bem_building_facts(-1), class = "bayesbem_error_argument")
  expect_error(bem_building_facts(100, floors = 0), class = "bayesbem_error_argument")
})

test_that("an uncooled building uses no cooling electricity and floats above its set point", {
  p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  cooled <- bem_building_facts(2000, floors = 2)
  uncooled <- bem_building_facts(2000, floors = 2, cooling = FALSE)
  monthly <- epw_monthly(shipped_epw(2013))
  a <- bem_monthly(p, monthly, cooled)
  b <- bem_monthly(p, monthly, uncooled)
  expect_gt(sum(a$cooling_need), 0)
  expect_equal(b$cooling_need, rep(0, 12))
  expect_equal(b$electricity, a$electricity - a$cooling_need / p$dx_cooling_cop)
  expect_equal(b$gas, a$gas)
  hourly <- epw_weather(shipped_epw(2013), by = "hour")
  h <- bem_hourly(p, hourly, uncooled)
  expect_equal(sum(h$cooling_need), 0)
  expect_gt(max(h$air_temp), p$cooling_setpoint + 1)
  expect_error(bem_building(cooling = "no"), class = "bayesbem_error_argument")
})
