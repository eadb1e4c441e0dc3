/* Time per step of an exported filter (kfw-cli export-c): NAME_predict and NAME_update_CHANNEL
   over a dataset held in memory, repeated, in ns per row. Built and run by
   bench/c_export_bench.sh, which passes the header (-DEXPORT_H), the update (-DUPDATE), the
   state type (-DSTATE), init and predict (-DINIT, -DPREDICT), the inputs' and the channel's sizes
   (-DNIN, -DNZ); the data file holds t, the inputs and the channel's components, comma-separated,
   one row per line. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include EXPORT_H

#define MAX_ROWS 200000

static double rows[MAX_ROWS][1 + NIN + NZ];

int main(int argc, char **argv) {
  FILE *in;
  long n = 0, k;
  int rep, reps, j;
  double best = INFINITY, sink = 0.0;
  if (argc != 3) {
    fprintf(stderr, "usage: %s DATA.csv REPEATS\n", argv[0]);
    return 2;
  }
  in = fopen(argv[1], "r");
  if (!in) return 2;
  while (n < MAX_ROWS) {
    for (j = 0; j <= NIN + NZ; ++j) {
      if (fscanf(in, j ? ",%lf" : "%lf", &rows[n][j]) != 1) goto done;
    }
    ++n;
  }
done:
  fclose(in);
  reps = atoi(argv[2]);
  for (rep = 0; rep < reps; ++rep) {
    STATE s;
    struct timespec a, b;
    double ns;
    clock_gettime(CLOCK_MONOTONIC, &a);
    INIT(&s);
    for (k = 0; k < n; ++k) {
      REAL z[NZ], u[NIN + 1], nis;
      if (k > 0) {
        for (j = 0; j < NIN; ++j) u[j] = (REAL)rows[k - 1][1 + j];
        PREDICT(&s, u, (REAL)rows[k - 1][0], (REAL)(rows[k][0] - rows[k - 1][0]));
      }
      for (j = 0; j < NZ; ++j) z[j] = (REAL)rows[k][1 + NIN + j];
      UPDATE(&s, z, &nis);
    }
    clock_gettime(CLOCK_MONOTONIC, &b);
    sink += s.x[0];
    ns = ((double)(b.tv_sec - a.tv_sec) * 1e9 + (double)(b.tv_nsec - a.tv_nsec)) / (double)n;
    if (ns < best) best = ns;
  }
  printf("%ld rows, best of %d: %.1f ns per row (checksum %g)\n", n, reps, best, sink);
  return 0;
}
