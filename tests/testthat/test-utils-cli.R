test_that("and_list() joins items as a sentence does", {
  and_list <- bayesbem:::and_list
  expect_equal(and_list(character()), character())
  expect_equal(and_list("a"), "a")
  expect_equal(and_list(c("a", "b")), "a and b")
  expect_equal(and_list(c("a", "b", "c")), "a, b and c")
})
