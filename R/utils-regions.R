# The grammar of region terms ("b > c", "a, where b < c"), shared by
# explain_discrepancy() that names them, extend() that adds them and
# predict() that computes them from new data.

# A region's name: "b > c" for a step (effect ""), "a, where b < c".
region_label <- function(effect, input, side, cut) {
  label <- vapply(cut, format, character(1), digits = 15)
  where <- sprintf("%s, where %s %s %s", effect, input, side, label)
  ifelse(rep_len(nzchar(effect), length(where)), where, sprintf("%s %s %s", input, side, label))
}

# The values of a region term named as explain_discrepancy() prints it ("a,
# where b < c", "b > c") or as a covariate column ("a:b<c", "b>c"), from the
# columns of `table`: a where b <= c (or b > c), 0 elsewhere; a step is 1
# where b > c. NULL when `name` is no such name or names columns `table`
# lacks.
region_values <- function(name, table) {
  parts <- parse_region(name)
  if (is.null(parts) || !all(setdiff(c(parts$effect, parts$input), "") %in% names(table))) {
    return(NULL)
  }
  inside <- if (parts$side == ">") table[[parts$input]] > parts$cut else table[[parts$input]] <= parts$cut
  if (nzchar(parts$effect)) table[[parts$effect]] * inside else as.numeric(inside)
}

# A region's name split into the candidate whose effect it restricts
# (`effect`, "" for a step), the `input` it is a region of, the `side`
# ("<" or ">") and the `cut`; NULL when `name` is no region.
parse_region <- function(name) {
  compact <- region_column_name(name)
  parts <- regmatches(compact, regexec("^(?:([^:]+):)?([^<>]+)([<>])(.+)$", compact))[[1]]
  cut <- suppressWarnings(as.numeric(parts[5]))
  if (length(parts) == 0L || is.na(cut)) {
    return(NULL)
  }
  list(effect = parts[2], input = parts[3], side = parts[4], cut = cut)
}

# The candidates a term is made of: a region's effect and input, or the
# candidate itself.
term_variables <- function(name) {
  parts <- parse_region(name)
  if (is.null(parts)) name else setdiff(c(parts$effect, parts$input), "")
}

# A region's name as a covariate column (and in `gamma[<name>]`): no commas
# or spaces, "occupancy, where temp > 14.9" -> "occupancy:temp>14.9".
region_column_name <- function(region) {
  gsub(" ", "", sub(", where ", ":", region, fixed = TRUE), fixed = TRUE)
}
