  int<lower=1> n;                        // field observations
  int<lower=1> mt;                       // simulation runs
  int<lower=1> p;                        // observable inputs x
  int<lower=1> q;                        // calibration parameters t
  vector[n] y;                           // field output
  matrix[n, p] xf;                       // field inputs
  matrix[mt, q] tc;                      // simulation design, one row per run
