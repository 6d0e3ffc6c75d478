# A fit with the additive discrepancy, as far as its conditionals read it.
additive_fit_parts <- function(d, design = bayesbem:::hsgp_design(m = 6, boundary = 3)) {
  structure(list(data = d, emulator = list(basis = bayesbem:::basis_emulator(d, variance = 0.99)),
                 settings = list(discrepancy_kernel = "additive", hsgp = design)),
            class = "bayesbem_fit")
}

test_that("the additive conditionals at linear cost are the dense Gaussian conditionals", {
  withr::local_seed(31)
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  d$field$time <- as.POSIXct("2013-07-01", tz = "UTC") + 3600 * c(0:4, 7:10)
  d$names$period <- "time"
  segments <- rep(1:2, c(5, 4))
  x_new <- matrix(stats::runif(4 * d$p), 4)
  n <- d$n
  months <- rep(c("2013-07", "2013-08", "2013-09"), c(3, 4, 2))
  shift_of <- bayesbem:::shift_columns(months)
  # white noise, then AR(1) noise; then each with a shift per month
  for (case in list(c(0, 0), c(0, 0), c(0.7, 0), c(-0.5, 0), c(0, 1), c(0.6, 1))) {
    phi <- case[1]
    shifts <- case[2] == 1
    fit <- additive_fit_parts(d)
    if (phi != 0) fit$settings$noise_correlation <- "ar1"
    if (shifts) fit$settings[c("noise_shift", "shifts")] <- list("month", list(months))
    ag <- bayesbem:::additive_geometry(fit)
    basis <- fit$emulator$basis
    design <- fit$settings$hsgp
    xf <- bayesbem:::field_grid_inputs(d)
    r_cor <- reference_ar1_cor(phi, segments)
    par <- list(tf = stats::runif(d$q, 0.1, 0.9), beta_delta = stats::rexp(d$p, 0.5),
                lambda_delta = stats::rgamma(1, 10, 1), lambda_e = stats::rgamma(1, 10, 0.1),
                gamma = numeric(0), phi = phi, lambda_shift = if (shifts) 20 else Inf)
    # dense: y - mu = eta_c + delta + e, eta_c ~ N(B w(tf), B V B' + s2r R)
    wv <- bayesbem:::basis_weights(basis, par$tf)
    c_eta <- basis$B %*% (wv$var * t(basis$B)) + basis$s2r * r_cor
    k_ff <- bayesbem:::hsgp_cov(xf, xf, design, par$beta_delta, par$lambda_delta)
    k_sf <- bayesbem:::hsgp_cov(x_new, xf, design, par$beta_delta, par$lambda_delta)
    k_ss <- bayesbem:::hsgp_cov(x_new, x_new, design, par$beta_delta, par$lambda_delta)
    # the months' shifts l ~ N(0, I / lambda_shift), M l a part of the noise
    k_l <- if (shifts) diag(3) / par$lambda_shift else matrix(0, 0, 0)
    m_l <- if (shifts) shift_of else matrix(0, n, 0)
    sigma <- c_eta + k_ff + r_cor / par$lambda_e + m_l %*% k_l %*% t(m_l)
    resid <- d$y - basis$mu - drop(basis$B %*% wv$mean)
    si <- solve(sigma)
    cross <- rbind(c_eta, k_sf, k_l %*% t(m_l))
    nl <- ncol(m_l)
    dense_mean <- c(basis$mu + drop(basis$B %*% wv$mean), numeric(4 + nl)) +
      drop(cross %*% si %*% resid)
    prior_cov <- matrix(0, n + 4 + nl, n + 4 + nl)
    prior_cov[1:n, 1:n] <- c_eta
    prior_cov[n + 1:4, n + 1:4] <- k_ss
    prior_cov[n + 4 + seq_len(nl), n + 4 + seq_len(nl)] <- k_l
    dense_cov <- prior_cov - cross %*% si %*% t(cross)
    # low rank: a = a0 + s z, the field rows' emulator mu + B w + t, t given a
    post <- bayesbem:::additive_posterior(ag, par)
    ma <- post$a0 + post$s * post$z
    ca <- (post$s %o% post$s) * chol2inv(post$r)
    pc <- ag$pc
    w_cols <- cbind(basis$B, matrix(0, n, ncol(ag$u) - pc))
    m_eta <- w_cols - basis$s2r / post$d * ag$u
    m_delta <- cbind(matrix(0, 4, pc), bayesbem:::hsgp_phi(x_new, design), matrix(0, 4, nl))
    m_shift <- cbind(matrix(0, nl, ncol(ag$u) - nl), diag(nl))
    m_all <- rbind(m_eta, m_delta, m_shift)
    low_mean <- c(basis$mu + drop(m_eta %*% ma) + basis$s2r / post$d * ag$r0,
                  drop(m_delta %*% ma), drop(m_shift %*% ma))
    low_cov <- m_all %*% ca %*% t(m_all)
    low_cov[1:n, 1:n] <- low_cov[1:n, 1:n] + basis$s2r * (1 - basis$s2r / post$d) * r_cor
    expect_equal(low_mean, dense_mean, tolerance = 1e-8, ignore_attr = TRUE)
    expect_equal(low_cov, dense_cov, tolerance = 1e-8, ignore_attr = TRUE)
  }
})

test_that("additive draws follow the conditional, at field rows and anywhere for delta", {
  withr::local_seed(32)
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  fit <- additive_fit_parts(d)
  ag <- bayesbem:::additive_geometry(fit)
  par <- list(tf = rep(0.5, d$q), beta_delta = rep(2, d$p), lambda_delta = 5, lambda_e = 50,
              gamma = numeric(0))
  post <- bayesbem:::additive_posterior(ag, par)
  ma <- post$a0 + post$s * post$z
  x_new <- matrix(stats::runif(2 * d$p), 2)
  at <- c(3L, 7L)
  phi <- bayesbem:::hsgp_phi(x_new, fit$settings$hsgp)
  draws <- replicate(4000, unlist(bayesbem:::additive_draw(ag, par, at, phi)))
  pc <- ag$pc
  expected <- c(ag$basis$mu[at] + drop(ag$u[at, 1:pc] %*% ma[1:pc]) +
                  ag$basis$s2r / post$d * (ag$r0[at] - drop(ag$u[at, ] %*% ma)),
                drop(phi %*% ma[-(1:pc)]))
  se <- apply(draws, 1, stats::sd) / sqrt(ncol(draws))
  expect_true(all(abs(rowMeans(draws) - expected) < 4 * se))
})

test_that("an additive fit predicts eta only at its field rows", {
  d <- random_grid_data(n = 9, runs = 8, extra = 2)
  fit <- additive_fit_parts(d)
  x <- d$field[d$names$x]
  expect_equal(bayesbem:::field_row_of(d, x[c(4, 2, 4), ]), c(4L, 2L, 4L))
  moved <- x[1:2, ]
  moved[2, 1] <- moved[2, 1] + 1
  expect_error(bayesbem:::field_row_of(d, moved), class = "bayesbem_error_newdata")
  expect_snapshot(bayesbem:::field_row_of(d, moved), error = TRUE)
})
