  target += gamma_lpdf(lambda_delta | lambda_delta_shape, lambda_delta_rate);
  target += gamma_lpdf(lambda_e | lambda_e_shape, lambda_e_rate);
  target += tf_prior_lpdf(tf | tf_is_normal, tf_mu, tf_sd, tf_scale, tf_lo, tf_span, tf_v_lo,
                            tf_v_span);
  target += normal_lpdf(gamma | 0, gamma_sd);
