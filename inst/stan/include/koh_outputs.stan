  /* The first row of output k's block among rows stacked by output (output
   * 1's rows, then output 2's, ...) and the block's size, from each row's
   * output (1 to K). Counted rather than passed: integer arrays have no
   * syntax that both the old and the new Stan compilers take. */
  int output_start(vector output, int k) {
    int start = 1;
    for (i in 1:rows(output)) {
      if (output[i] < k) {
        start += 1;
      }
    }
    return start;
  }

  int output_size(vector output, int k) {
    int count = 0;
    for (i in 1:rows(output)) {
      if (output[i] == k) {
        count += 1;
      }
    }
    return count;
  }

  /* The parametric discrepancy terms h * gamma at rows s to s + len - 1, an
   * output's block (zero when there are none, as discrepancy_terms()). */
  vector output_terms(matrix h, vector gamma, int s, int len) {
    if (cols(h) == 0) {
      return rep_vector(0, len);
    }
    return block(h, s, 1, len, cols(h)) * gamma;
  }
