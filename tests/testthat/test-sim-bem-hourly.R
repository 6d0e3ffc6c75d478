initial_params <- function() {
  stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
}

# `hours` hours of constant weather, from Monday 0:00.
constant_weather <- function(hours, temp, dni = 0, dhi = 0, ghi = 0) {
  data.frame(temp = temp, dni = dni, dhi = dhi, ghi = ghi, hour = (seq_len(hours) - 1L) %% 24L,
             weekday = ((seq_len(hours) - 1L) %/% 24L) %% 7L + 1L)
}

test_that("in steady state the heating power is the network's conductance times the difference", {
  b <- bem_building(window_fraction = 0.15, occupant_gain = 0, fan_flow = 0)
  p <- initial_params()
  p$lighting_power_density <- 0
  p$equipment_power_density <- 0
  out <- bem_hourly(p, constant_weather(24 * 20, temp = -5), b)
  # by hand: air to outdoors through ventilation, and through the surface
  # node to the windows and the opaque elements (the mass path H_tr_ms in
  # series with H_tr_em is H_tr_op by construction)
  a_window <- 0.15 * 106.8
  h_op <- 0.5 * (106.8 - a_window) + 0.2 * 79 + 0.5 * 0.4 * 79
  h_w <- 2.9 * a_window
  h_ve <- 1206 * (0.001524 * (106.8 + 79) + 0.03)
  h_is <- 3.45 * 4.5 * 79
  conductance <- h_ve + 1 / (1 / h_is + 1 / (h_w + h_op))
  last <- nrow(out)
  expect_equal(out$heating_need[last], conductance * (18.3 - -5) / 1000, tolerance = 1e-6)
  expect_equal(out$air_temp[last], 18.3)
  expect_equal(out$cooling_need[last], 0)
  # the meters as the monthly model splits them, an hour at a time: the
  # baseboard's share up to its capacity (1.5 kW binds at -5 C), gas the rest
  need <- out$heating_need[last]
  expect_equal(out$electricity[last], 1.5)
  expect_equal(out$gas[last], (need - 1.5) / 0.95)
  # between the set points the building floats: no heating, no cooling
  mild <- bem_hourly(p, constant_weather(48, temp = 21), b)
  expect_true(all(mild$heating_need == 0 & mild$cooling_need == 0))
  expect_true(all(mild$air_temp > 18.3 & mild$air_temp < 23.9))
})

test_that("lights and equipment follow occupancy with the monthly model's mean", {
  p <- initial_params()
  b <- bem_building()
  week <- bem_hourly(p, constant_weather(168 * 2, temp = 20), b)
  lights_and_equipment <- (0.6 * p$lighting_power_density + 0.7 * p$equipment_power_density) * 79
  fan <- 0.45 * 500 / p$fan_total_efficiency
  # without heating or cooling, electricity is lights, equipment and fan
  other <- week$electricity * 1000 - fan - week$cooling_need * 1000 / p$dx_cooling_cop
  expect_equal(mean(other), lights_and_equipment, tolerance = 1e-9)
  # occupied weekday hours use more than nights and weekends
  expect_gt(other[10], other[3])
  expect_gt(other[10], other[24 * 5 + 10])
  expect_error(bem_building(occupancy = rep(1, 24)), class = "bayesbem_error_argument")
  expect_error(bem_building(occupancy = rep(2, 168)), class = "bayesbem_error_argument")
})

test_that("its monthly totals agree with the monthly model's", {
  epw <- shipped_epw(2013)
  w <- epw_weather(epw, by = "hour")
  p <- initial_params()
  h <- bem_hourly(p, w)
  m <- bem_monthly(p, epw_monthly(epw))
  elec <- as.vector(tapply(h$electricity, w$month, sum))
  gas <- as.vector(tapply(h$gas, w$month, sum))
  # the tolerance stated: annual totals within 5 %, monthly electricity
  # within 15 %, the gas of heating months (a tenth of the peak or more)
  # within 10 %
  expect_lt(abs(sum(elec) / sum(m$electricity) - 1), 0.05)
  expect_lt(abs(sum(gas) / sum(m$gas) - 1), 0.05)
  expect_lt(max(abs(elec / m$electricity - 1)), 0.15)
  heating <- m$gas > 0.1 * max(m$gas)
  expect_lt(max(abs(gas[heating] / m$gas[heating] - 1)), 0.10)
})

test_that("hourly weather is every record, dated in the file's standard time", {
  epw <- shipped_epw(2013)
  w <- epw_weather(epw, by = "hour")
  hourly <- bayesbem:::read_epw_hourly(epw)
  expect_equal(nrow(w), 8760)
  expect_equal(w$temp, hourly$temp)
  # record 1 ends at 1:00 on 1 January: its hour starts at 0:00, UTC-7
  expect_equal(format(w$time[1], "%Y-%m-%d %H:%M %z"), "2013-01-01 00:00 -0700")
  expect_equal(w$hour[1:25], c(0:23, 0))
  expect_equal(w$weekday[1], 2)  # 1 January 2013 was a Tuesday
  expect_equal(sum(w$hours), 8760)
  expect_equal(as.vector(tapply(w$temp, w$month, mean)), epw_monthly(epw)$temp)
  # a typical year takes its weekdays from the header
  records <- readLines(epw)[-(1:8)]
  tmy <- epw_with_records(epw, sub("^2013,1,", "1999,1,", records))
  expect_equal(epw_weather(tmy, by = "hour")$weekday[1], 7)  # "Sunday" in the header
  # missing values stop an hourly model
  first <- strsplit(records[1], ",")[[1]]
  first[7] <- "99.9"
  gap <- epw_with_records(epw, c(paste(first, collapse = ","), records[-1]))
  expect_error(epw_weather(gap, by = "hour"), class = "bayesbem_error_weather")
})

test_that("the simulator by day, week or hour sums the hourly model", {
  epw <- shipped_epw(2013)
  design <- data.frame(equipment_power_density = 12)
  w <- epw_weather(epw, by = "hour")
  p <- initial_params()
  p$equipment_power_density <- 12
  h <- bem_hourly(p, w)
  hourly <- bem_simulator(epw, by = "hour", output = c("electricity", "gas"))
  expect_named(hourly$x, c("temp", "rh", "solar", "weekday", "daytype_hour"))
  # the hour of the day type: Monday to Friday 0-23, Saturday and Sunday 24-47
  weekend <- format(hourly$periods$start, "%u") %in% c("6", "7")
  expect_equal(hourly$x$daytype_hour, as.integer(format(hourly$periods$start, "%H")) + 24 * weekend)
  runs <- simulate_design(hourly, design)
  expect_equal(runs$eta[runs$output == "gas"], h$gas)
  daily <- bem_simulator(epw, by = "day")
  expect_named(daily$x, c("temp", "rh", "solar", "weekday"))
  expect_equal(simulate_design(daily, design)$eta, as.vector(tapply(h$electricity, w$date, sum)))
  weekly <- simulate_design(bem_simulator(epw, by = "week"), design)$eta
  day <- as.integer(w$date - w$date[1])
  expect_equal(weekly, as.vector(tapply(h$electricity, day %/% 7, sum)))
  expect_error(bem_simulator(epw_monthly(epw), by = "day"), class = "bayesbem_error_argument")
  expect_error(bem_simulator(epw, by = "day", periods = data.frame(start = "2013-01-01",
                                                                   end = "2013-01-31")),
               class = "bayesbem_error_argument")
})

test_that("schedules follow the building's clock, summer time and holidays", {
  weather <- epw_weather(shipped_epw(2013), by = "hour")
  at <- function(text) which(format(weather$time, "%Y-%m-%d %H:%M") == text)
  plain <- bayesbem:::schedule_hours(weather, bem_building())
  denver <- bem_building(clock = "America/Denver", holidays = as.Date("2013-07-04"))
  local <- bayesbem:::schedule_hours(weather, denver)
  # Monday 1 July, 6:00 standard time, is 7:00 on Denver's summer clock
  expect_equal(plain[at("2013-07-01 06:00")], 7L)
  expect_equal(local[at("2013-07-01 06:00")], 8L)
  # in January the clock is standard time
  expect_equal(local[weather$month == 1], plain[weather$month == 1])
  # Independence Day (a Thursday) keeps Sunday's hours
  expect_equal(local[at("2013-07-04 11:00")], 6L * 24L + 12L + 1L)
  p <- stats::setNames(as.list(bem_parameters()$initial), bem_parameters()$parameter)
  noon <- at("2013-07-04 11:00")
  expect_lt(bem_hourly(p, weather, denver)$electricity[noon],
            bem_hourly(p, weather)$electricity[noon])
  # the simulator's inputs are the schedules' hours
  sim <- bem_simulator(shipped_epw(2013), building = denver, by = "hour")
  expect_equal(sim$x$daytype_hour[noon], 24 + 12)
  expect_error(bem_building(clock = "Mars/Olympus"), class = "bayesbem_error_argument")
  expect_error(bem_building(holidays = "2013-07-04"), class = "bayesbem_error_argument")
})

test_that("a heating plant on a timer lets the air fall to its setback and reheats", {
  p <- initial_params()
  cold <- constant_weather(168 * 3, temp = -5)
  # plant on at 6:00-19:59 every day, off otherwise with the air held above 12 C
  day <- as.numeric(0:23 >= 6 & 0:23 < 20)
  timer <- bem_building(heating_schedule = rep(day, 7), heating_setback = 12)
  always <- bem_hourly(p, cold, bem_building())
  timed <- bem_hourly(p, cold, timer)
  off <- cold$hour < 6 | cold$hour >= 20
  last_day <- seq(nrow(cold) - 23, nrow(cold))
  # the air cools at night, never below the setback, and is held while on
  expect_true(all(timed$air_temp[off] >= 12 - 1e-9 & timed$air_temp[off] < 18.3))
  expect_equal(timed$air_temp[last_day][7:20], rep(18.3, 14))
  # the first hour on reheats the cooled mass, the need then falls as it warms
  expect_true(all(diff(timed$heating_need[last_day][7:20]) < 0))
  expect_gt(timed$heating_need[last_day][7], timed$heating_need[last_day][6])
  expect_lt(sum(timed$heating_need), sum(always$heating_need))
  # a plant always on, or off with the setback at the set point, is the default
  expect_equal(bem_hourly(p, cold, bem_building(heating_schedule = rep(1, 168))), always)
  expect_equal(bem_hourly(p, cold, bem_building(heating_schedule = rep(0, 168),
                                                heating_setback = 18.3)), always)
  # the monthly model holds the set point's mean over the week
  w <- epw_monthly(shipped_epw(2013))
  mean_setpoint <- 12 + mean(rep(day, 7)) * (18.3 - 12)
  p_mean <- p
  p_mean$heating_setpoint <- mean_setpoint
  expect_equal(bem_monthly(p, w, timer)$heating_need, bem_monthly(p_mean, w)$heating_need)
  expect_error(bem_building(heating_schedule = rep(1, 24)), "heating_schedule",
               class = "bayesbem_error_argument")
  expect_error(bem_building(heating_setback = "12"), "heating_setback",
               class = "bayesbem_error_argument")
})
