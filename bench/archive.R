# The Cambridge University Estates building energy archive (Langtry &
# Choudhary 2024, doi 10.5281/zenodo.10955332, MIT) for the benchmarks on
# real buildings (bench-real-buildings.R, bench-portfolio.R real):
# sourced with `archive` set to the archive's git directory or checkout.
# Buildings 19, 57 and 111 are kept for acceptance.
held_for_acceptance <- c("19", "57", "111")

# A file of the archive, from a checkout or from its git directory (NULL
# when absent).
archive_csv <- function(path) {
  if (file.exists(file.path(archive, path))) {
    return(utils::read.csv(file.path(archive, path), check.names = FALSE))
  }
  text <- system2("git", c("--git-dir", shQuote(archive), "show", shQuote(paste0("HEAD:", path))),
                  stdout = TRUE, stderr = FALSE)
  if (length(text) == 0L) return(NULL)
  utils::read.csv(text = text, check.names = FALSE)
}

# Stops when any of `buildings` is kept for acceptance.
refuse_held_out <- function(buildings) {
  if (any(buildings %in% held_for_acceptance)) {
    stop("buildings 19, 57 and 111 are kept for acceptance", call. = FALSE)
  }
}

# A building's meter readings of a year (time in UTC, value), NULL without.
archive_meter <- function(b, meter, year) {
  refuse_held_out(b)
  archive_csv(sprintf("building_data/processed_data/UCam_Building_b%s/%s/%s.csv", b, meter, year))
}

# A building's facts as the archive gives them
# (building_floor_roof_areas.csv): its gross internal area (m2), floors and
# approximate roof area (m2).
archive_facts <- function(b) {
  refuse_held_out(b)
  areas <- archive_csv("building_data/processed_data/building_floor_roof_areas.csv")
  row <- areas[areas[[1]] == paste0("b", b), ]
  if (nrow(row) != 1L) stop("the archive gives no areas of building ", b, call. = FALSE)
  list(floor_area = row[[2]], floors = row[[3]], roof_area = row[[4]])
}

# The Met Office's hourly weather at Bedford for a year, through
# read_weather() and write_epw(): the EPW file's path. The station stamps
# each hour by its end, so the year's hours run into the next year's file.
archive_epw <- function(year) {
  station <- do.call(rbind, lapply(as.integer(year) + 0:1, function(y) {
    archive_csv(sprintf("aux_data/MetOffice Weather Data/processed_data/bedford/%d.csv", y))
  }))
  names(station) <- c("time", "temp", "rh", "ghi")
  weather <- suppressMessages(read_weather(station, latitude = 52.227, longitude = -0.465,
                                           elevation = 85, time_zone = 0, name = "Bedford",
                                           days = as.Date(paste0(year, c("-01-01", "-12-31")))))
  write_epw(weather, file.path(tempdir(), sprintf("bedford-%s.epw", year)))
}
