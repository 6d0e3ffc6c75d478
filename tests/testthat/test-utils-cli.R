test_that("and_list() joins items as a sentence does", {
  and_list <- bayesbem:::and_list
  expect_equal(and_list(character()), character())
  expect_equal(and_list("a"), "a")
  expect_equal(and_list(c("a", "b")), "a and b")
  expect_equal(and_list(c("a", "b", "c")), "a, b and c")
})

test_that("a long table prints its first rows and its last, saying how many are left out", {
  df <- data.frame(period = c(seq_len(99), NA), savings = c(seq_len(99) / 3, 1650))
  out <- capture.output(bayesbem:::print_rounded(df, 3))
  expect_length(out, 23)
  expect_match(out[22], "1650")
  expect_equal(out[23], "(rows 21 to 99 of 100 not shown)")
  expect_length(capture.output(bayesbem:::print_rounded(df[1:50, ], 3)), 51)
})
