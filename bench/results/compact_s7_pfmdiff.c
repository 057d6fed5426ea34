/* pfmdiff A.pfm B.pfm: pixels (RGB) that differ, the largest absolute and relative difference */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
static int ch = 3;
static float* load(const char* p, int* w, int* h) {
    FILE* f = fopen(p, "rb");
    if (!f) return NULL;
    char t[3] = {0};
    double sc;
    if (fscanf(f, "%2s %d %d %lf", t, w, h, &sc) != 4 || (t[1] != 'F' && t[1] != 'f')) { fclose(f); return NULL; }
    ch = t[1] == 'F' ? 3 : 1;
    fgetc(f);
    size_t n = (size_t)*w * *h * ch;
    float* d = malloc(n * 4);
    if (d && fread(d, 4, n, f) != n) { free(d); d = NULL; }
    fclose(f);
    return d;
}
int main(int argc, char** argv) {
    int w1, h1, w2, h2;
    if (argc < 3) return 2;
    float *a = load(argv[1], &w1, &h1), *b = load(argv[2], &w2, &h2);
    if (!a || !b || w1 != w2 || h1 != h2) { printf("pfmdiff: cannot compare\n"); return 1; }
    size_t n = (size_t)w1 * h1, px = 0, big = 0;
    double mx = 0, mr = 0, sum = 0;
    for (size_t i = 0; i < n; i++) {
        int d = 0;
        for (int k = 0; k < ch; k++) {
            double x = a[ch * i + k], y = b[ch * i + k], e = fabs(x - y), r = e / fmax(fabs(x), 1e-6);
            if (x != y) d = 1;
            if (e > mx) mx = e;
            if (r > mr) mr = r;
            if (r > 1e-3) big++;
            sum += fabs(x);
        }
        px += d;
    }
    printf("%zu of %zu pixels differ (%.4f%%), largest difference %.3g (relative %.3g), %zu channels off by more than 1e-3 relative; mean value %.4g\n",
           px, n, 100.0 * px / n, mx, mr, big, sum / ((double)ch * n));
    return 0;
}
