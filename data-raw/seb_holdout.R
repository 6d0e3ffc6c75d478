# Builds `seb_holdout`, six measured bills of the case-study building for
# January-June 2012 with that period's monthly weather (the held-out test of
# the paper's Table 3). Run from the package root with bayesbem installed:
#   Rscript data-raw/seb_holdout.R
bills <- utils::read.csv("data-raw/bills_2012_jan_jun.csv")
stopifnot(nrow(bills) == 6L, identical(names(bills), c("period_start", "period_end", "kwh")))

weather <- bayesbem::epw_monthly(file.path("inst", "extdata", "2012_AMY.epw.gz"))[1:6, ]
seb_holdout <- data.frame(y = bills$kwh, temp = weather$temp, rh = weather$rh,
                          solar = weather$dni, month = weather$date,
                          bill_start = as.Date(bills$period_start),
                          bill_end = as.Date(bills$period_end))
save(seb_holdout, file = "data/seb_holdout.rda", compress = "xz", version = 2)
