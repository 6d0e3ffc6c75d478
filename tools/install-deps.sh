#!/usr/bin/env bash
# Installs everything bayesbem needs on a bare Debian bookworm machine:
# R and the prebuilt r-cran-* packages from Debian, an optimised BLAS
# (OpenBLAS, serial: the chains already share the cores), time zones (meter
# data in local time), then from CRAN only
# what Debian lacks. Needs root (or sudo). Safe to run again.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  r-base-dev libx11-6 pandoc tzdata \
  r-cran-rstan r-cran-rstantools r-cran-stanheaders r-cran-bh libboost-dev \
  r-cran-rcppeigen r-cran-rcppparallel r-cran-rcpp \
  r-cran-posterior r-cran-bayesplot r-cran-loo r-cran-ggplot2 \
  r-cran-checkmate r-cran-cli r-cran-codetools r-cran-rlang r-cran-withr \
  r-cran-lhs r-cran-future r-cran-future.apply r-cran-progressr \
  r-cran-batchtools r-cran-future.batchtools r-cran-callr \
  r-cran-testthat r-cran-roxygen2 r-cran-knitr r-cran-rmarkdown r-cran-vdiffr \
  r-cran-rcpparmadillo r-cran-proxy r-cran-clue r-cran-ggrepel r-cran-rspectra \
  r-cran-shinyjs r-cran-iterators r-cran-modeltools r-cran-foreach \
  r-cran-dbi r-cran-rsqlite r-cran-jsonlite \
  libopenblas0-serial \
  > /dev/null
echo "install-deps: Debian packages installed"
# Debian's alternatives switch R to OpenBLAS when it is installed; say which
# BLAS R now uses (calibrate() reads the same to choose its linear algebra).
Rscript -e 'cat("install-deps: R uses the BLAS at", extSoftVersion()[["BLAS"]], "\n")'

# From CRAN (R's configured repository) only what Debian lacks: sensitivity
# (Morris screening) and the few of its dependencies Debian does not ship
# (dtwclust, a hard dependency of sensitivity, is most of the time: make
# compiles its C++ on every core). bayesbem calls only sensitivity's R code
# (morris()), so their C and C++ are compiled without optimisation or
# debugging symbols, and quietly (R_MAKEVARS_USER: these builds alone;
# bench/results/install-times.md).
makevars="$(mktemp)"
trap 'rm -f "$makevars"' EXIT
for v in CFLAGS CXXFLAGS CXX11FLAGS CXX14FLAGS CXX17FLAGS; do
  echo "$v = -O0 -g0 -w" >> "$makevars"
done
R_MAKEVARS_USER="$makevars" MAKEFLAGS="${MAKEFLAGS:--j$(nproc)}" Rscript -e '
cran_only <- c("sensitivity")
missing <- cran_only[!vapply(cran_only, requireNamespace, logical(1), quietly = TRUE)]
if (length(missing) > 0L) install.packages(missing, Ncpus = parallel::detectCores(), quiet = TRUE)
still <- cran_only[!vapply(cran_only, requireNamespace, logical(1), quietly = TRUE)]
if (length(still) > 0L) stop("could not install from CRAN: ", paste(still, collapse = ", "))
'
echo "install-deps: CRAN packages installed"
