/* The two-block wall's Moreau–Jean step in C: a line-by-line transcription of wall_truth/engine.py
 * (TwoBlockWall._contacts, _solve, _pgs, step, _crush_update), for speed. validate.py checks that the two agree.
 * Built by wall_truth/kernel.py with the system's C compiler; called through ctypes. */
#include <math.h>
#include <string.h>

#define MAXF 41
#define MAXSLOT (2 * MAXF + 8)
#define MAXR (2 * MAXF + 8)
enum { P_B, P_H1, P_H2, P_RHO, P_G, P_FP, P_MU, P_MUG, P_BETA, P_KIND, P_NF, P_K, P_C, P_FC, P_NPAR };
enum { S_Q = 0, S_V = 6, S_DON = 12, S_DV = 13, S_DF = 14, S_FB = 15, S_STAT = 16 };
#define S_CG (S_STAT + MAXSLOT)
#define S_CJ (S_CG + MAXF)
#define S_SIZE (S_CJ + MAXF)
enum { NORMAL = 0, TANGENT = 1, EQUALITY = 2 };

typedef struct {
  double J[6];
  int kind;
  double off, C, cap;
  int group, slot, ftag, fj;
} Row;

int wt_state_size(void) { return S_SIZE; }
int wt_param_size(void) { return P_NPAR; }

typedef struct {
  double b, h1, h2, g, Fp, mu, mug, beta, m1, m2, J1, J2, minv[6];
  int crushing, nf;
  double fs[MAXF], fk[MAXF], fc[MAXF], fcap[MAXF];
} Wall;

static void wall_from(const double *p, Wall *w) {
  w->b = p[P_B]; w->h1 = p[P_H1]; w->h2 = p[P_H2]; w->g = p[P_G]; w->Fp = p[P_FP];
  w->mu = p[P_MU]; w->mug = p[P_MUG]; w->beta = p[P_BETA];
  double rho = p[P_RHO], b = w->b;
  w->m1 = rho * b * w->h1; w->m2 = rho * b * w->h2;
  w->J1 = w->m1 * (b * b + w->h1 * w->h1) / 12.0;
  w->J2 = w->m2 * (b * b + w->h2 * w->h2) / 12.0;
  w->minv[0] = w->minv[1] = 1 / w->m1; w->minv[2] = 1 / w->J1;
  w->minv[3] = w->minv[4] = 1 / w->m2; w->minv[5] = 1 / w->J2;
  w->crushing = p[P_KIND] > 0.5;
  w->nf = (int)p[P_NF];
  if (w->crushing) {
    int n = w->nf;
    for (int i = 0; i < n; ++i) {
      double wi = b / (n - 1);
      if (i == 0 || i == n - 1) wi = 0.5 * b / (n - 1);
      w->fs[i] = (-0.5 + (double)i / (n - 1)) * b;
      w->fk[i] = p[P_K] * wi; w->fc[i] = p[P_C] * wi; w->fcap[i] = p[P_FC] * wi;
    }
  }
}

void wt_init(const double *p, double *s) {
  memset(s, 0, sizeof(double) * S_SIZE);
  s[S_Q + 1] = p[P_H1] / 2; s[S_Q + 4] = p[P_H1] + p[P_H2] / 2;
  for (int i = 0; i < MAXSLOT; ++i) s[S_STAT + i] = -1;
}

static void prow(const double *q, int blk, double px, double py, double dx, double dy, double *J) {
  for (int i = 0; i < 6; ++i) J[i] = 0.0;
  if (blk == 1) {
    double rx = px - q[0], ry = py - q[1];
    J[0] = dx; J[1] = dy; J[2] = rx * dy - ry * dx;
  } else {
    double rx = px - q[3], ry = py - q[4];
    J[3] = dx; J[4] = dy; J[5] = rx * dy - ry * dx;
  }
}
static void rel(const double *q, double px, double py, double dx, double dy, int a, int bb, double *J) {
  double ja[6], jb[6];
  prow(q, a, px, py, dx, dy, ja); prow(q, bb, px, py, dx, dy, jb);
  for (int i = 0; i < 6; ++i) J[i] = ja[i] - jb[i];
}

static int contacts(const Wall *w, const double *s, double h, Row *rows) {
  const double *q = s + S_Q;
  double b = w->b, h1 = w->h1, h2 = w->h2, hb = 0.5 * b, near = 0.004;
  double X1 = q[0], Y1 = q[1], f1 = q[2], X2 = q[3], Y2 = q[4], f2 = q[5];
  double c1 = cos(f1), s1 = sin(f1), c2 = cos(f2), s2 = sin(f2);
  double n1x = -s1, n1y = c1, t1x = c1, t1y = s1, n2x = s2, n2y = -c2, t2x = c2, t2y = s2;
  double top1x = X1 - s1 * h1 / 2, top1y = Y1 + c1 * h1 / 2;
  double bot2x = X2 + s2 * h2 / 2, bot2y = Y2 - c2 * h2 / 2;
  double bot1x = X1 + s1 * h1 / 2, bot1y = Y1 - c1 * h1 / 2;
  double tol_face = 0.02 * b;
  int m = 0, nf = w->nf;
#define NOFF(gap) ((gap) >= 0 ? (gap) / h : w->beta * (gap) / h)
#define ADD(kind_, off_, C_, cap_, group_, slot_, ftag_, fj_) \
  do { rows[m].kind = kind_; rows[m].off = off_; rows[m].C = C_; rows[m].cap = cap_; rows[m].group = group_; \
       rows[m].slot = slot_; rows[m].ftag = ftag_; rows[m].fj = fj_; ++m; } while (0)
  int slot_gt, slot_j0, slot_jt, slot_t0, slot_tt0, slot_drv;
  if (!w->crushing) { slot_gt = 2; slot_j0 = 3; slot_jt = 7; slot_t0 = 8; slot_tt0 = 10; slot_drv = 12; }
  else { slot_gt = nf; slot_j0 = nf + 1; slot_jt = 2 * nf + 1; slot_t0 = 2 * nf + 2; slot_tt0 = 2 * nf + 4; slot_drv = 2 * nf + 6; }
  /* ground */
  if (!w->crushing) {
    for (int k = 0; k < 2; ++k) {
      double sx = k ? 1.0 : -1.0;
      double px = X1 + c1 * sx * hb - s1 * (-h1 / 2), py = Y1 + s1 * sx * hb + c1 * (-h1 / 2);
      double gap = py;
      if (gap < near) { prow(q, 1, px, py, 0.0, 1.0, rows[m].J); ADD(NORMAL, NOFF(gap), 0.0, INFINITY, 0, k, 0, 0); }
    }
  } else {
    for (int j = 0; j < nf; ++j) {
      double sj = w->fs[j];
      double px = X1 + c1 * sj + s1 * h1 / 2, py = Y1 + s1 * sj - c1 * h1 / 2;
      double gap = py + s[S_CG + j];
      if (gap < near) {
        double k = w->fk[j], c = w->fc[j], C = 1.0 / (h * h * k + h * c);
        prow(q, 1, px, py, 0.0, 1.0, rows[m].J);
        ADD(NORMAL, k * gap / (h * k + c), C, h * w->fcap[j], 0, j, 1, j);
      }
    }
  }
  prow(q, 1, bot1x, bot1y, 1.0, 0.0, rows[m].J); ADD(TANGENT, 0.0, 0.0, INFINITY, 0, slot_gt, 0, 0);
  /* joint */
  if (!w->crushing) {
    for (int k = 0; k < 2; ++k) {
      double sx = k ? 1.0 : -1.0;
      double px = X2 + c2 * sx * hb - s2 * (-h2 / 2), py = Y2 + s2 * sx * hb + c2 * (-h2 / 2);
      double dx = px - top1x, dy = py - top1y;
      double gap = dx * n1x + dy * n1y, along = dx * t1x + dy * t1y;
      if (gap < near && fabs(along) <= hb + tol_face) { rel(q, px, py, n1x, n1y, 2, 1, rows[m].J); ADD(NORMAL, NOFF(gap), 0.0, INFINITY, 1, slot_j0 + k, 0, 0); }
    }
    for (int k = 0; k < 2; ++k) {
      double sx = k ? 1.0 : -1.0;
      double px = X1 + c1 * sx * hb - s1 * (h1 / 2), py = Y1 + s1 * sx * hb + c1 * (h1 / 2);
      double dx = px - bot2x, dy = py - bot2y;
      double gap = dx * n2x + dy * n2y, along = dx * t2x + dy * t2y;
      if (gap < near && fabs(along) <= hb + tol_face) { rel(q, px, py, n2x, n2y, 1, 2, rows[m].J); ADD(NORMAL, NOFF(gap), 0.0, INFINITY, 1, slot_j0 + 2 + k, 0, 0); }
    }
  } else {
    for (int j = 0; j < nf; ++j) {
      double sj = w->fs[j];
      double px = X2 + c2 * sj + s2 * h2 / 2, py = Y2 + s2 * sj - c2 * h2 / 2;
      double dx = px - top1x, dy = py - top1y;
      double gapg = dx * n1x + dy * n1y, gap = gapg + s[S_CJ + j], along = dx * t1x + dy * t1y;
      if (gap < near && fabs(along) <= hb + tol_face) {
        double k = w->fk[j], c = w->fc[j], C = 1.0 / (h * h * k + h * c);
        rel(q, px, py, n1x, n1y, 2, 1, rows[m].J);
        ADD(NORMAL, k * gap / (h * k + c), C, h * w->fcap[j], 1, slot_j0 + j, 2, j);
      }
    }
  }
  rel(q, top1x, top1y, t1x, t1y, 2, 1, rows[m].J); ADD(TANGENT, 0.0, 0.0, INFINITY, 1, slot_jt, 0, 0);
  /* top guides */
  for (int k = 0; k < 2; ++k) {
    double sx = k ? 1.0 : -1.0;
    double px = X2 + c2 * sx * hb - s2 * (h2 / 2), py = Y2 + s2 * sx * hb + c2 * (h2 / 2);
    double gap = sx < 0 ? (px + hb) : (hb - px);
    if (gap < near) { prow(q, 2, px, py, -sx, 0.0, rows[m].J); ADD(NORMAL, NOFF(gap), 0.0, INFINITY, 2 + k, slot_t0 + k, 0, 0); }
  }
  if (w->mug > 0) {
    for (int k = 0; k < 2; ++k) {
      double sx = k ? 1.0 : -1.0;
      double px = X2 + c2 * sx * hb - s2 * (h2 / 2), py = Y2 + s2 * sx * hb + c2 * (h2 / 2);
      prow(q, 2, px, py, 0.0, 1.0, rows[m].J); ADD(TANGENT, 0.0, 0.0, INFINITY, 2 + k, slot_tt0 + k, 0, 0);
    }
  }
  if (s[S_DON] > 0.5) { prow(q, 1, top1x, top1y, 1.0, 0.0, rows[m].J); ADD(EQUALITY, -s[S_DV], 0.0, INFINITY, -1, slot_drv, 0, 0); }
  return m;
#undef NOFF
#undef ADD
}

static int gauss(int m, double *A, double *x) { /* A: m x m row-major, x: rhs in, solution out */
  for (int c = 0; c < m; ++c) {
    int piv = c; double best = fabs(A[c * m + c]);
    for (int r = c + 1; r < m; ++r) if (fabs(A[r * m + c]) > best) { best = fabs(A[r * m + c]); piv = r; }
    if (best == 0.0) return -1;
    if (piv != c) {
      for (int k = 0; k < m; ++k) { double t = A[c * m + k]; A[c * m + k] = A[piv * m + k]; A[piv * m + k] = t; }
      double t = x[c]; x[c] = x[piv]; x[piv] = t;
    }
    for (int r = c + 1; r < m; ++r) {
      double f = A[r * m + c] / A[c * m + c];
      if (f == 0.0) continue;
      for (int k = c; k < m; ++k) A[r * m + k] -= f * A[c * m + k];
      x[r] -= f * x[c];
    }
  }
  for (int r = m - 1; r >= 0; --r) {
    double acc = x[r];
    for (int k = r + 1; k < m; ++k) acc -= A[r * m + k] * x[k];
    x[r] = acc / A[r * m + r];
  }
  return 0;
}

static double mu_of(const Wall *w, int grp) { return grp <= 1 ? w->mu : w->mug; }

static void pgs(const Wall *w, int m, const Row *rows, const double *W, const double *q, double *P) {
  for (int i = 0; i < m; ++i) if (rows[i].kind == NORMAL && P[i] < 0) P[i] = 0.0;
  for (int sweep = 0; sweep < 5000; ++sweep) {
    double delta = 0.0;
    for (int i = 0; i < m; ++i) {
      double u = q[i];
      for (int j = 0; j < m; ++j) u += W[i * m + j] * P[j];
      double d = W[i * m + i] + (rows[i].kind == NORMAL ? rows[i].C : 0.0);
      if (d <= 0) continue;
      double nw;
      if (rows[i].kind == NORMAL) {
        nw = P[i] - (u + rows[i].C * P[i]) / d;
        if (nw < 0.0) nw = 0.0;
        if (nw > rows[i].cap) nw = rows[i].cap;
      } else if (rows[i].kind == TANGENT) {
        double lim = 0.0;
        for (int j = 0; j < m; ++j) if (rows[j].kind == NORMAL && rows[j].group == rows[i].group) lim += P[j];
        lim *= mu_of(w, rows[i].group);
        nw = P[i] - u / d;
        if (nw < -lim) nw = -lim;
        if (nw > lim) nw = lim;
      } else {
        nw = P[i] - u / d;
      }
      if (fabs(nw - P[i]) > delta) delta = fabs(nw - P[i]);
      P[i] = nw;
    }
    if (delta < 1e-13) break;
  }
}

static void solve(const Wall *w, double *s, int m, const Row *rows, const double *W, const double *q, double *P) {
  int st[MAXR], nw[MAXR];
  double A[MAXR * MAXR], U[MAXR];
  for (int i = 0; i < m; ++i) {
    double v = s[S_STAT + rows[i].slot];
    st[i] = v < 0 ? (rows[i].kind == NORMAL ? 0 : 1) : (int)v;
    if (rows[i].kind == NORMAL && st[i] == 2 && !isfinite(rows[i].cap)) st[i] = 1;
  }
  double dmax = W[0];
  for (int i = 1; i < m; ++i) if (W[i * m + i] > dmax) dmax = W[i * m + i];
  double eps = 1e-9 * dmax, tolv = 1e-10, tolp = 1e-12;
  int converged = 0;
  for (int i = 0; i < m; ++i) P[i] = 0.0;
  for (int it = 0; it < 40; ++it) {
    for (int i = 0; i < m; ++i) {
      int wrow = st[i] == 1 || rows[i].kind == EQUALITY;
      for (int j = 0; j < m; ++j) A[i * m + j] = wrow ? W[i * m + j] : 0.0;
      double reg = (rows[i].kind == NORMAL ? rows[i].C : 0.0) + eps;
      A[i * m + i] = wrow ? A[i * m + i] + reg : 1.0;
      P[i] = wrow ? -q[i] : ((rows[i].kind == NORMAL && st[i] == 2) ? rows[i].cap : 0.0);
    }
    for (int i = 0; i < m; ++i) {
      if (rows[i].kind == TANGENT && st[i] >= 2) {
        double mu = mu_of(w, rows[i].group);
        double sg = st[i] == 2 ? mu : -mu;
        for (int j = 0; j < m; ++j) if (rows[j].kind == NORMAL && rows[j].group == rows[i].group) A[i * m + j] -= sg;
      }
    }
    if (gauss(m, A, P) != 0) break;
    for (int i = 0; i < m; ++i) {
      double u = q[i];
      for (int j = 0; j < m; ++j) u += W[i * m + j] * P[j];
      U[i] = u;
    }
    int same = 1;
    for (int i = 0; i < m; ++i) {
      nw[i] = st[i];
      if (rows[i].kind == NORMAL) {
        double wv = U[i] + rows[i].C * P[i];
        if (st[i] == 1 && P[i] < -tolp) nw[i] = 0;
        else if (st[i] == 1 && isfinite(rows[i].cap) && P[i] > rows[i].cap) nw[i] = 2;
        else if (st[i] == 0 && wv < -tolv) nw[i] = 1;
        else if (st[i] == 2 && wv > tolv) nw[i] = 1;
      }
    }
    for (int i = 0; i < m; ++i) {
      if (rows[i].kind != TANGENT) continue;
      int grp = rows[i].group;
      double mu = mu_of(w, grp), N = 0.0;
      for (int j = 0; j < m; ++j) if (rows[j].kind == NORMAL && rows[j].group == grp && st[j] > 0) N += P[j];
      int sv = st[i];
      if (N <= 0.0 || mu <= 0.0) nw[i] = 0;
      else if (sv == 0) nw[i] = 1;
      else if (sv == 1 && fabs(P[i]) > mu * N * (1 + 1e-9) + tolp) nw[i] = P[i] > 0 ? 2 : 3;
      else if (sv == 2 && U[i] > tolv) nw[i] = 1;
      else if (sv == 3 && U[i] < -tolv) nw[i] = 1;
    }
    for (int i = 0; i < m; ++i) if (nw[i] != st[i]) same = 0;
    if (same) { converged = 1; break; }
    for (int i = 0; i < m; ++i) st[i] = nw[i];
  }
  if (!converged) {
    s[S_FB] += 1;
    pgs(w, m, rows, W, q, P);
    for (int i = 0; i < m; ++i) {
      if (rows[i].kind == NORMAL) st[i] = P[i] <= 0 ? 0 : (P[i] >= rows[i].cap ? 2 : 1);
      else if (rows[i].kind == TANGENT) st[i] = 1;
    }
  }
  for (int i = 0; i < MAXSLOT; ++i) s[S_STAT + i] = -1;
  for (int i = 0; i < m; ++i) s[S_STAT + rows[i].slot] = st[i];
}

static void crush_update(const Wall *w, double *s, int m, const Row *rows, const double *P) {
  const double *q = s + S_Q;
  double X1 = q[0], Y1 = q[1], f1 = q[2], X2 = q[3], Y2 = q[4], f2 = q[5];
  double c1 = cos(f1), s1 = sin(f1), c2 = cos(f2), s2 = sin(f2);
  double top1x = X1 - s1 * w->h1 / 2, top1y = Y1 + c1 * w->h1 / 2;
  for (int i = 0; i < m; ++i) {
    if (rows[i].ftag == 0 || P[i] < rows[i].cap * (1 - 1e-9)) continue;
    int j = rows[i].fj;
    double sj = w->fs[j], k = w->fk[j];
    if (rows[i].ftag == 1) {
      double gap = Y1 + s1 * sj - c1 * w->h1 / 2;
      double d = -gap - w->fcap[j] / k;
      if (d > s[S_CG + j]) s[S_CG + j] = d;
    } else {
      double px = X2 + c2 * sj + s2 * w->h2 / 2, py = Y2 + s2 * sj - c2 * w->h2 / 2;
      double gap = (px - top1x) * (-s1) + (py - top1y) * c1;
      double d = -gap - w->fcap[j] / k;
      if (d > s[S_CJ + j]) s[S_CJ + j] = d;
    }
  }
}

void wt_step(const double *p, double *s, double h, double ug) {
  Wall w;
  wall_from(p, &w);
  Row rows[MAXR];
  int m = contacts(&w, s, h, rows);
  double *q = s + S_Q, *v = s + S_V;
  double rtx = -sin(q[5]) * w.h2 / 2;
  double f[6] = {-w.m1 * ug, -w.m1 * w.g, 0.0, -w.m2 * ug, -w.m2 * w.g - w.Fp, -rtx * w.Fp};
  double vfree[6];
  for (int i = 0; i < 6; ++i) vfree[i] = v[i] + h * w.minv[i] * f[i];
  double W[MAXR * MAXR], qv[MAXR], P[MAXR];
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      double acc = 0.0;
      for (int k = 0; k < 6; ++k) acc += rows[i].J[k] * w.minv[k] * rows[j].J[k];
      W[i * m + j] = acc;
    }
    double acc = 0.0;
    for (int k = 0; k < 6; ++k) acc += rows[i].J[k] * vfree[k];
    qv[i] = acc + rows[i].off;
  }
  solve(&w, s, m, rows, W, qv, P);
  for (int k = 0; k < 6; ++k) {
    double acc = 0.0;
    for (int i = 0; i < m; ++i) acc += rows[i].J[k] * w.minv[k] * P[i];
    v[k] = vfree[k] + acc;
  }
  for (int k = 0; k < 6; ++k) q[k] = q[k] + h * v[k];
  for (int i = 0; i < m; ++i) if (rows[i].kind == EQUALITY) s[S_DF] = P[i] / h;
  if (w.crushing) crush_update(&w, s, m, rows, P);
}

/* n steps of size h; the ground acceleration at each step's middle, linear from ug0 (start) to ug1 (end) */
void wt_steps(const double *p, double *s, double h, int n, double ug0, double ug1) {
  for (int k = 0; k < n; ++k) {
    double a = (k + 0.5) / n;
    wt_step(p, s, h, ug0 + a * (ug1 - ug0));
  }
}
