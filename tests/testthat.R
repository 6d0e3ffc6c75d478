library(testthat)
library(bayesbem)

test_check("bayesbem")
