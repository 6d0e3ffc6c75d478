# Extracts the few files of the Cambridge University Estates building energy
# archive (Langtry & Choudhary 2024, v2.1, doi 10.5281/zenodo.10955332, MIT;
# github.com/EECi/Cambridge-Estates-Building-Energy-Archive, commit
# 97b8a6b79a66296f54bf4f0c74c23b7d6b541bae) that vignettes/real-building.Rmd
# reads, into inst/extdata/cambridge/, gzip-compressed and otherwise as the
# archive has them: building 33's hourly electricity and gas of 2019 (UTC
# stamps, missing readings stored as zeros) and the Met Office's hourly
# observations at Bedford for 2019, with the first hour of 2020 (the
# station stamps each hour by its end), and building 33's row of the
# archive's floor and roof areas. Run from the package root with the
# archive fetched as a git directory or checked out:
#   CAMBRIDGE_ARCHIVE=<archive> Rscript data-raw/cambridge.R
archive <- Sys.getenv("CAMBRIDGE_ARCHIVE")
stopifnot(nzchar(archive))
archive_lines <- function(path) {
  if (file.exists(file.path(archive, path))) return(readLines(file.path(archive, path)))
  system2("git", c("--git-dir", shQuote(archive), "show", shQuote(paste0("HEAD:", path))),
          stdout = TRUE)
}
out <- "inst/extdata/cambridge"
dir.create(out, showWarnings = FALSE)
write_gz <- function(lines, file) {
  con <- gzfile(file.path(out, file), "w")
  writeLines(lines, con)
  close(con)
}
for (meter in c("electricity", "gas")) {
  write_gz(archive_lines(sprintf("building_data/processed_data/UCam_Building_b33/%s/2019.csv", meter)),
           sprintf("b33-%s-2019.csv.gz", meter))
}
station <- "aux_data/MetOffice Weather Data/processed_data/bedford/%d.csv"
write_gz(c(archive_lines(sprintf(station, 2019)), archive_lines(sprintf(station, 2020))[2]),
         "bedford-2019.csv.gz")
areas <- archive_lines("building_data/processed_data/building_floor_roof_areas.csv")
writeLines(c(areas[1], grep("^b33,", areas, value = TRUE)), file.path(out, "b33-areas.csv"))
