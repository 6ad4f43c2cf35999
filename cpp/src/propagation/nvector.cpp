// satgnc's serial N_Vector. Each kernel performs exactly the floating-point operations, in the same
// order, as SUNDIALS 6.4 NVECTOR_SERIAL with fused operations disabled (then the generic layer
// falls back to sequences of N_VScale / N_VLinearSum / N_VDotProd / N_VWrmsNorm). The fused kernels
// below are single-pass versions of those fall-backs, so results are bitwise identical while the loops
// are compiled with our flags instead of Debian's unoptimised libsundials.
#include "detail/nvector.hpp"

#include <cmath>
#include <cstdlib>
#include <new>

namespace satgnc::propagation {

namespace {

struct Content {
  sunindextype length = 0;
  bool own = false;
  realtype* data = nullptr;
};

inline Content* content(N_Vector v) { return static_cast<Content*>(v->content); }
inline realtype* data(N_Vector v) { return content(v)->data; }
inline sunindextype len(N_Vector v) { return content(v)->length; }
inline realtype rsqrt(realtype x) { return x <= 0.0 ? 0.0 : std::sqrt(x); }

N_Vector_ID get_id(N_Vector) { return SUNDIALS_NVEC_CUSTOM; }
sunindextype get_length(N_Vector v) { return len(v); }
realtype* get_array(N_Vector v) { return data(v); }
void set_array(realtype* d, N_Vector v) {
  if (len(v) > 0) content(v)->data = d;
}

void destroy(N_Vector v) {
  if (v == nullptr) return;
  if (v->content != nullptr) {
    Content* c = content(v);
    if (c->own) std::free(c->data);
    delete c;
    v->content = nullptr;
  }
  N_VFreeEmpty(v);
}

N_Vector clone_empty(N_Vector w) {
  N_Vector v = N_VNewEmpty(w->sunctx);
  if (v == nullptr) return nullptr;
  if (N_VCopyOps(w, v) != 0) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  Content* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = len(w);
  v->content = c;
  return v;
}

N_Vector clone(N_Vector w) {
  N_Vector v = clone_empty(w);
  if (v == nullptr) return nullptr;
  const sunindextype n = len(w);
  if (n > 0) {
    auto* d = static_cast<realtype*>(std::malloc(sizeof(realtype) * static_cast<size_t>(n)));
    if (d == nullptr) {
      destroy(v);
      return nullptr;
    }
    content(v)->data = d;
    content(v)->own = true;
  }
  return v;
}

void space(N_Vector v, sunindextype* lrw, sunindextype* liw) {
  *lrw = len(v);
  *liw = 1;
}

// z = a x + b y with NVECTOR_SERIAL's special cases (they change rounding: a == b gives a (x + y)).
void linear_sum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  const realtype* yd = data(y);
  realtype* zd = data(z);
  if (b == 1.0 && z == y) {  // y <- a x + y (a = +-1 give identical bits)
    for (sunindextype i = 0; i < n; ++i) zd[i] += a * xd[i];
    return;
  }
  if (a == 1.0 && z == x) {  // x <- b y + x
    for (sunindextype i = 0; i < n; ++i) zd[i] += b * yd[i];
    return;
  }
  if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
    return;
  }
  if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] - yd[i];
    return;
  }
  if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = yd[i] - xd[i];
    return;
  }
  if (a == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = b * yd[i] + xd[i];
    return;
  }
  if (b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] + yd[i];
    return;
  }
  if (a == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = b * yd[i] - xd[i];
    return;
  }
  if (b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] - yd[i];
    return;
  }
  if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
    return;
  }
  if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
    return;
  }
  for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
}

void set_const(realtype c, N_Vector z) {
  const sunindextype n = len(z);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = c;
}

void prod(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = len(x);
  const realtype *xd = data(x), *yd = data(y);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] * yd[i];
}

void div(N_Vector x, N_Vector y, N_Vector z) {
  const sunindextype n = len(x);
  const realtype *xd = data(x), *yd = data(y);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] / yd[i];
}

// c = +-1 (copy / negate) give the same bits as c * x.
void scale(realtype c, N_Vector x, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = c * xd[i];
}

void vabs(N_Vector x, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = std::fabs(xd[i]);
}

void inv(N_Vector x, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_const(N_Vector x, realtype b, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + b;
}

realtype dot(N_Vector x, N_Vector y) {
  const sunindextype n = len(x);
  const realtype *xd = data(x), *yd = data(y);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) sum += xd[i] * yd[i];
  return sum;
}

realtype max_norm(N_Vector x) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype m = 0.0;
  for (sunindextype i = 0; i < n; ++i)
    if (std::fabs(xd[i]) > m) m = std::fabs(xd[i]);
  return m;
}

realtype wsqrsum(N_Vector x, N_Vector w) {
  const sunindextype n = len(x);
  const realtype *xd = data(x), *wd = data(w);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    const realtype p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

realtype wsqrsum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const sunindextype n = len(x);
  const realtype *xd = data(x), *wd = data(w), *idd = data(id);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    if (idd[i] > 0.0) {
      const realtype p = xd[i] * wd[i];
      sum += p * p;
    }
  }
  return sum;
}

realtype wrms_norm(N_Vector x, N_Vector w) { return rsqrt(wsqrsum(x, w) / len(x)); }
realtype wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return rsqrt(wsqrsum_mask(x, w, id) / len(x));
}

realtype vmin(N_Vector x) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype m = xd[0];
  for (sunindextype i = 1; i < n; ++i)
    if (xd[i] < m) m = xd[i];
  return m;
}

realtype wl2_norm(N_Vector x, N_Vector w) { return rsqrt(wsqrsum(x, w)); }

realtype l1_norm(N_Vector x) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) sum += std::fabs(xd[i]);
  return sum;
}

void compare(realtype c, N_Vector x, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = (std::fabs(xd[i]) >= c) ? 1.0 : 0.0;
}

booleantype inv_test(N_Vector x, N_Vector z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  realtype* zd = data(z);
  booleantype ok = SUNTRUE;
  for (sunindextype i = 0; i < n; ++i) {
    if (xd[i] == 0.0)
      ok = SUNFALSE;
    else
      zd[i] = 1.0 / xd[i];
  }
  return ok;
}

booleantype constr_mask(N_Vector c, N_Vector x, N_Vector m) {
  const sunindextype n = len(x);
  const realtype *cd = data(c), *xd = data(x);
  realtype* md = data(m);
  realtype temp = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    const bool test =
        (std::fabs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) || (std::fabs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0);
    if (test) temp = md[i] = 1.0;
  }
  return temp == 1.0 ? SUNFALSE : SUNTRUE;
}

realtype min_quotient(N_Vector num, N_Vector denom) {
  const sunindextype n = len(num);
  const realtype *nd = data(num), *dd = data(denom);
  bool first = true;
  realtype m = BIG_REAL;
  for (sunindextype i = 0; i < n; ++i) {
    if (dd[i] == 0.0) continue;
    const realtype q = nd[i] / dd[i];
    if (first) {
      m = q;
      first = false;
    } else {
      m = m < q ? m : q;
    }
  }
  return m;
}

// ---- fused operations: single-pass versions of the generic fall-backs (same bits) -------------

// Fall-back: z = c0 X0; then z = c_i X_i + z, one full vector at a time. When some X_i (i >= 1)
// is z itself, stage i reads the partial sum, which the store-through loop reproduces.
int linear_combination(int nvec, realtype* c, N_Vector* X, N_Vector z) {
  const sunindextype n = len(z);
  realtype* zd = data(z);
  bool alias = false;
  for (int i = 1; i < nvec; ++i) alias = alias || (X[i] == z);
  if (alias) {
    for (sunindextype j = 0; j < n; ++j) {
      zd[j] = c[0] * data(X[0])[j];
      for (int i = 1; i < nvec; ++i) zd[j] += c[i] * data(X[i])[j];
    }
    return 0;
  }
  if (nvec == 2) {
    const realtype *x0 = data(X[0]), *x1 = data(X[1]);
    const realtype c0 = c[0], c1 = c[1];
    for (sunindextype j = 0; j < n; ++j) {
      const realtype t = c0 * x0[j];
      zd[j] = t + c1 * x1[j];
    }
    return 0;
  }
  for (sunindextype j = 0; j < n; ++j) {
    realtype t = c[0] * data(X[0])[j];
    for (int i = 1; i < nvec; ++i) t += c[i] * data(X[i])[j];
    zd[j] = t;
  }
  return 0;
}

// Fall-back: Z_i = a_i x + Y_i through N_VLinearSum(a_i, x, 1, Y_i, Z_i), all cases give a x + y.
int scale_add_multi(int nvec, realtype* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  const sunindextype n = len(x);
  const realtype* xd = data(x);
  for (int i = 0; i < nvec; ++i) {
    const realtype* yd = data(Y[i]);
    realtype* zd = data(Z[i]);
    const realtype ai = a[i];
    for (sunindextype j = 0; j < n; ++j) zd[j] = ai * xd[j] + yd[j];
  }
  return 0;
}

int dot_multi(int nvec, N_Vector x, N_Vector* Y, realtype* d) {
  for (int i = 0; i < nvec; ++i) d[i] = dot(x, Y[i]);
  return 0;
}

int linear_sum_array(int nvec, realtype a, N_Vector* X, realtype b, N_Vector* Y, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) linear_sum(a, X[i], b, Y[i], Z[i]);
  return 0;
}

int scale_array(int nvec, realtype* c, N_Vector* X, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) scale(c[i], X[i], Z[i]);
  return 0;
}

int const_array(int nvec, realtype c, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) set_const(c, Z[i]);
  return 0;
}

int wrms_array(int nvec, N_Vector* X, N_Vector* W, realtype* nrm) {
  for (int i = 0; i < nvec; ++i) nrm[i] = wrms_norm(X[i], W[i]);
  return 0;
}

int wrms_mask_array(int nvec, N_Vector* X, N_Vector* W, N_Vector id, realtype* nrm) {
  for (int i = 0; i < nvec; ++i) nrm[i] = wrms_norm_mask(X[i], W[i], id);
  return 0;
}

// Fall-back (no scaleaddmulti there): Z[j][i] = a_j X_i + Y[j][i].
int scale_add_multi_array(int nvec, int nsum, realtype* a, N_Vector* X, N_Vector** Y, N_Vector** Z) {
  for (int i = 0; i < nvec; ++i) {
    const sunindextype n = len(X[i]);
    const realtype* xd = data(X[i]);
    for (int j = 0; j < nsum; ++j) {
      const realtype* yd = data(Y[j][i]);
      realtype* zd = data(Z[j][i]);
      const realtype aj = a[j];
      for (sunindextype k = 0; k < n; ++k) zd[k] = aj * xd[k] + yd[k];
    }
  }
  return 0;
}

// Fall-back: Z_i = c_0 X[0][i]; Z_i = c_j X[j][i] + Z_i.
int linear_combination_array(int nvec, int nsum, realtype* c, N_Vector** X, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) {
    const sunindextype n = len(Z[i]);
    realtype* zd = data(Z[i]);
    for (sunindextype k = 0; k < n; ++k) {  // store-through: safe when Z_i aliases some X[j][i]
      zd[k] = c[0] * data(X[0][i])[k];
      for (int j = 1; j < nsum; ++j) zd[k] += c[j] * data(X[j][i])[k];
    }
  }
  return 0;
}

}  // namespace

N_Vector nvector_new(sunindextype n, SUNContext ctx) {
  N_Vector v = N_VNewEmpty(ctx);
  if (v == nullptr) return nullptr;
  N_Vector_Ops o = v->ops;
  o->nvgetvectorid = get_id;
  o->nvclone = clone;
  o->nvcloneempty = clone_empty;
  o->nvdestroy = destroy;
  o->nvspace = space;
  o->nvgetarraypointer = get_array;
  o->nvsetarraypointer = set_array;
  o->nvgetlength = get_length;
  o->nvgetlocallength = get_length;
  o->nvlinearsum = linear_sum;
  o->nvconst = set_const;
  o->nvprod = prod;
  o->nvdiv = div;
  o->nvscale = scale;
  o->nvabs = vabs;
  o->nvinv = inv;
  o->nvaddconst = add_const;
  o->nvdotprod = dot;
  o->nvmaxnorm = max_norm;
  o->nvwrmsnorm = wrms_norm;
  o->nvwrmsnormmask = wrms_norm_mask;
  o->nvmin = vmin;
  o->nvwl2norm = wl2_norm;
  o->nvl1norm = l1_norm;
  o->nvcompare = compare;
  o->nvinvtest = inv_test;
  o->nvconstrmask = constr_mask;
  o->nvminquotient = min_quotient;
  o->nvlinearcombination = linear_combination;
  o->nvscaleaddmulti = scale_add_multi;
  o->nvdotprodmulti = dot_multi;
  o->nvlinearsumvectorarray = linear_sum_array;
  o->nvscalevectorarray = scale_array;
  o->nvconstvectorarray = const_array;
  o->nvwrmsnormvectorarray = wrms_array;
  o->nvwrmsnormmaskvectorarray = wrms_mask_array;
  o->nvscaleaddmultivectorarray = scale_add_multi_array;
  o->nvlinearcombinationvectorarray = linear_combination_array;
  o->nvdotprodlocal = dot;
  o->nvmaxnormlocal = max_norm;
  o->nvminlocal = vmin;
  o->nvl1normlocal = l1_norm;
  o->nvinvtestlocal = inv_test;
  o->nvconstrmasklocal = constr_mask;
  o->nvminquotientlocal = min_quotient;
  o->nvwsqrsumlocal = wsqrsum;
  o->nvwsqrsummasklocal = wsqrsum_mask;
  o->nvdotprodmultilocal = dot_multi;

  Content* c = new (std::nothrow) Content;
  if (c == nullptr) {
    N_VFreeEmpty(v);
    return nullptr;
  }
  c->length = n;
  v->content = c;
  if (n > 0) {
    c->data = static_cast<realtype*>(std::malloc(sizeof(realtype) * static_cast<size_t>(n)));
    if (c->data == nullptr) {
      destroy(v);
      return nullptr;
    }
    c->own = true;
  }
  return v;
}

double* nvector_data(N_Vector v) { return data(v); }

bool nvector_is_satgnc(N_Vector v) { return v != nullptr && v->ops->nvgetvectorid == get_id; }

}  // namespace satgnc::propagation
