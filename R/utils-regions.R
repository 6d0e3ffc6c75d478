# The grammar of region terms ("b > c", "a, where b < c") and hinges
# ("max(x - c, 0)", "max(c - x, 0)"), shared by explain_discrepancy() that
# names them, extend() that adds them and predict() that computes them
# from new data.

# A region's name: "b > c" for a step (effect ""), "a, where b < c".
region_label <- function(effect, input, side, cut) {
  label <- vapply(cut, format, character(1), digits = 15)
  where <- sprintf("%s, where %s %s %s", effect, input, side, label)
  ifelse(rep_len(nzchar(effect), length(where)), where, sprintf("%s %s %s", input, side, label))
}

# A hinge's name: "max(x - c, 0)" (side ">"; "max(x + 5, 0)" for c = -5),
# "max(c - x, 0)" (side "<").
hinge_label <- function(input, side, cut) {
  n <- max(length(side), length(cut))
  cut <- rep_len(cut, n)
  label <- vapply(cut, format, character(1), digits = 15)
  above <- sprintf("max(%s %s %s, 0)", input, ifelse(cut < 0, "+", "-"), sub("^-", "", label))
  ifelse(rep_len(side == ">", n), above, sprintf("max(%s - %s, 0)", label, input))
}

# Whether a term's name is a region-specific line, "a, where b > c".
is_line <- function(name) {
  parts <- parse_region(name)
  !is.null(parts) && nzchar(parts$effect)
}

# The columns a term adds to the discrepancy, named as covariate columns
# (region_column_name()): a step "b > c" or a hinge, one column; a
# region-specific line "a, where b > c" (an offset plus a slope in a inside
# the region, 0 outside), two: the region's step "b>c" first and the
# effect there "a:b>c", so that its offset and slope are one cause. NULL
# as region_values().
term_columns <- function(name, table) {
  parts <- parse_region(name)
  names <- region_column_name(name)
  if (is_line(name)) {
    names <- c(region_column_name(region_label("", parts$input, parts$side, parts$cut)), names)
  }
  columns <- lapply(stats::setNames(names, names), region_values, table = table)
  if (any(vapply(columns, is.null, logical(1)))) NULL else columns
}

# The values of one column of a region term named as explain_discrepancy()
# prints it or as a covariate column ("a, where b < c" or "a:b<c", "b > c"
# or "b>c", a hinge), from the columns of `table`: a where b <= c (or b >
# c), 0 elsewhere; a step is 1 where b > c. NULL when `name` is no such
# name or names columns `table` lacks.
region_values <- function(name, table) {
  hinge <- parse_hinge(name)
  if (!is.null(hinge)) {
    return(if (hinge$input %in% names(table)) hinge_values(hinge, table[[hinge$input]]))
  }
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

# A hinge's name split into its `input`, `side` and `cut` (spaces
# ignored): "max(x - c, 0)" rises with x above c (`side` ">"; a negative c
# reads "max(x + 5, 0)"), "max(c - x, 0)" with falling x below c ("<").
# NULL when `name` is no hinge.
parse_hinge <- function(name) {
  compact <- gsub(" ", "", name, fixed = TRUE)
  number <- "([0-9.]+(?:[eE][+-]?[0-9]+)?)"
  above <- regmatches(compact, regexec(paste0("^max\\(([A-Za-z._][A-Za-z0-9._]*)([+-])", number, ",0\\)$"),
                                       compact))[[1]]
  if (length(above) == 4L) {
    cut <- as.numeric(above[4])
    return(list(input = above[2], side = ">", cut = if (above[3] == "+") -cut else cut))
  }
  below <- regmatches(compact, regexec(paste0("^max\\((-?", substring(number, 2),
                                              "-([A-Za-z._][A-Za-z0-9._]*),0\\)$"), compact))[[1]]
  if (length(below) == 3L && !is.na(suppressWarnings(as.numeric(below[2])))) {
    return(list(input = below[3], side = "<", cut = as.numeric(below[2])))
  }
  NULL
}

# A hinge's values at input values `x`: max(x - c, 0) or max(c - x, 0).
hinge_values <- function(hinge, x) {
  if (hinge$side == ">") pmax(x - hinge$cut, 0) else pmax(hinge$cut - x, 0)
}

# The candidates a term is made of: a region's effect and input, a hinge's
# input, or the candidate itself.
term_variables <- function(name) {
  hinge <- parse_hinge(name)
  if (!is.null(hinge)) {
    return(hinge$input)
  }
  parts <- parse_region(name)
  if (is.null(parts)) name else setdiff(c(parts$effect, parts$input), "")
}

# A region's name as a covariate column (and in `gamma[<name>]`): no commas
# or spaces, "occupancy, where temp > 14.9" -> "occupancy:temp>14.9".
region_column_name <- function(region) {
  gsub(" ", "", sub(", where ", ":", region, fixed = TRUE), fixed = TRUE)
}
