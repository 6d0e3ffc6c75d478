#!/usr/bin/env bash
# Installs everything bayesbem needs on a bare Debian bookworm machine:
# R and the prebuilt r-cran-* packages from Debian, then from CRAN only what
# Debian lacks. Needs root (or sudo). Safe to run again.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  r-base-dev libx11-6 pandoc \
  r-cran-rstan r-cran-rstantools r-cran-stanheaders r-cran-bh libboost-dev \
  r-cran-rcppeigen r-cran-rcppparallel r-cran-rcpp \
  r-cran-posterior r-cran-bayesplot r-cran-loo r-cran-ggplot2 \
  r-cran-checkmate r-cran-cli r-cran-rlang r-cran-withr \
  r-cran-lhs r-cran-future r-cran-future.apply r-cran-progressr \
  r-cran-testthat r-cran-roxygen2 r-cran-knitr r-cran-rmarkdown r-cran-vdiffr \
  > /dev/null
echo "install-deps: Debian packages installed"
