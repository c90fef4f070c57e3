// solveSmallLp against GLPK's exact (rational) simplex on thousands of random instances, and on
// the two problems polydem solves with it: the Chebyshev centre of a polyhedron and the
// potential-block overlap test of Boon et al. (2012) (instances built from the faces of random
// polyhedron pairs, overlapping and apart); the optimal basis and multipliers it reports, and
// warm starts from a nearby problem's basis.
#include "polydem/geometry/small_lp.h"

#include <glpk.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "common/allocation_counter.h"
#include "polydem/core/error.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"

namespace polydem::geometry {
namespace {

using Status = SmallLpResult::Status;

struct Lp {
  std::vector<Vec4> rows;
  std::vector<double> b;
  Vec4 c = Vec4::Zero();

  void add(const Vec4& a, double rhs) {
    rows.push_back(a);
    b.push_back(rhs);
  }
  SmallLpResult solve() const { return solveSmallLp(rows, b, c); }
};

struct Reference {
  Status status = Status::kInfeasible;
  double objective = 0.0;
  Vec4 z = Vec4::Zero();
};

// GLPK's primal simplex and, with `exact`, then its rational simplex (glp_exact). glp_exact reads
// each double as the simplest fraction within a relative 1e-9 of it, so it is the exact optimum
// of the given data only when they are fractions with small denominators: instances solved
// exactly are drawn on a dyadic grid (denominators <= 1024), which also keeps b = a.v exact for
// rows built through a chosen vertex v.
Reference solveWithGlpk(const Lp& lp, bool exact) {
  glp_term_out(GLP_OFF);
  glp_prob* p = glp_create_prob();
  glp_set_obj_dir(p, GLP_MIN);
  glp_add_cols(p, 4);
  for (int k = 0; k < 4; ++k) {
    glp_set_col_bnds(p, k + 1, GLP_FR, 0.0, 0.0);
    glp_set_obj_coef(p, k + 1, lp.c[k]);
  }
  const int m = static_cast<int>(lp.rows.size());
  glp_add_rows(p, m);
  std::vector<int> ia{0}, ja{0};
  std::vector<double> ar{0.0};
  for (int i = 0; i < m; ++i) {
    glp_set_row_bnds(p, i + 1, GLP_UP, 0.0, lp.b[i]);
    for (int k = 0; k < 4; ++k) {
      if (lp.rows[i][k] == 0.0) continue;
      ia.push_back(i + 1);
      ja.push_back(k + 1);
      ar.push_back(lp.rows[i][k]);
    }
  }
  glp_load_matrix(p, static_cast<int>(ia.size()) - 1, ia.data(), ja.data(), ar.data());
  glp_smcp parm;
  glp_init_smcp(&parm);
  parm.msg_lev = GLP_MSG_OFF;
  // GLPK's default primal and dual tolerances (1e-7) let its optimum violate the rows of thin
  // polyhedra by ~5e-8 and undercut the true optimum by as much; ask for round-off.
  parm.tol_bnd = 1e-12;
  parm.tol_dj = 1e-12;
  if (glp_simplex(p, &parm) != 0) ADD_FAILURE() << "glp_simplex failed";
  if (exact && glp_exact(p, &parm) != 0) ADD_FAILURE() << "glp_exact failed";
  Reference ref;
  switch (glp_get_status(p)) {
    case GLP_OPT:
      ref.status = Status::kOptimal;
      ref.objective = glp_get_obj_val(p);
      for (int k = 0; k < 4; ++k) ref.z[k] = glp_get_col_prim(p, k + 1);
      break;
    case GLP_NOFEAS:
      ref.status = Status::kInfeasible;
      break;
    case GLP_UNBND:
      ref.status = Status::kUnbounded;
      break;
    default:
      ADD_FAILURE() << "GLPK gave status " << glp_get_status(p);
  }
  glp_delete_prob(p);
  return ref;
}

// The instance, printed when a check fails: rows as "a0 a1 a2 a3 <= b".
std::string describe(const Lp& lp) {
  std::ostringstream out;
  out.precision(17);
  out << "\nc = " << lp.c.transpose() << "\n";
  for (std::size_t i = 0; i < lp.rows.size(); ++i) {
    out << lp.rows[i].transpose() << " <= " << lp.b[i] << "\n";
  }
  return out.str();
}

const char* name(Status s) {
  switch (s) {
    case Status::kOptimal:
      return "optimal";
    case Status::kInfeasible:
      return "infeasible";
    case Status::kUnbounded:
      return "unbounded";
  }
  return "?";
}

// The size of the problem: the optimum's distance from the origin or the largest distance of a
// row's plane from it. Objectives are compared at |c| times this, excesses at |a_i| times this.
double problemSize(const Lp& lp, const Vec4& z) {
  double size = z.norm();
  for (std::size_t i = 0; i < lp.rows.size(); ++i) {
    const double n = lp.rows[i].norm();
    if (n > 0.0) size = std::max(size, std::abs(lp.b[i]) / n);
  }
  return size;
}

// Largest excess of a row over its right-hand side, relative to |a_i| times the problem size.
double worstRelativeExcess(const Lp& lp, const Vec4& z) {
  const double size = problemSize(lp, z);
  double worst = 0.0;
  for (std::size_t i = 0; i < lp.rows.size(); ++i) {
    const double excess = lp.rows[i].dot(z) - lp.b[i];
    if (excess > 0.0) worst = std::max(worst, excess / (lp.rows[i].norm() * size));
  }
  return worst;
}

// The optimal basis and multipliers: y >= 0, -c = sum_k y_k rows[basis[k]] / |rows[basis[k]]|
// over the real rows in the basis (box rows carry y = 0 at an optimum), and every real basis row
// active at z (complementary slackness).
void checkBasis(const Lp& lp, const SmallLpResult& got, const std::string& label) {
  const double size = problemSize(lp, got.z);
  Vec4 combination = Vec4::Zero();
  for (int k = 0; k < 4; ++k) {
    EXPECT_GE(got.multipliers[k], 0.0) << label;
    const int j = got.basis[k];
    if (j < 0) {
      EXPECT_EQ(got.multipliers[k], 0.0) << label;
      continue;
    }
    ASSERT_LT(j, static_cast<int>(lp.rows.size())) << label;
    const double norm = lp.rows[j].norm();
    combination += got.multipliers[k] * lp.rows[j] / norm;
    EXPECT_NEAR(lp.rows[j].dot(got.z), lp.b[j], 1e-9 * norm * size) << label << describe(lp);
  }
  EXPECT_LE((combination + lp.c).norm(), 1e-9 * lp.c.norm()) << label << describe(lp);
}

// The default rules, Bland's rule from the first pivot, and a fresh basis inverse at every pivot:
// every instance checks the anti-cycling and refactoring paths too.
const SmallLpOptions kOptionSets[] = {{}, {.bland_after = 0}, {.refactor_every = 1}};

// Status, objective (relative 1e-9) and feasibility of the point against GLPK, under each option
// set; returns GLPK's status.
Status checkAgainstGlpk(const Lp& lp, bool exact, const std::string& what) {
  const Reference ref = solveWithGlpk(lp, exact);
  for (const SmallLpOptions& options : kOptionSets) {
    const std::string label = what + " (bland_after " + std::to_string(options.bland_after) +
                              ", refactor_every " + std::to_string(options.refactor_every) + ")";
    const SmallLpResult got = solveSmallLp(lp.rows, lp.b, lp.c, options);
    EXPECT_EQ(name(got.status), std::string(name(ref.status))) << label << describe(lp);
    if (got.status == Status::kOptimal && ref.status == Status::kOptimal) {
      const double scale = lp.c.norm() * problemSize(lp, ref.z);
      EXPECT_NEAR(got.objective, ref.objective, 1e-9 * scale)
          << label << " excess: GLPK " << worstRelativeExcess(lp, ref.z) << ", ours "
          << worstRelativeExcess(lp, got.z) << describe(lp);
      EXPECT_NEAR(got.objective, lp.c.dot(got.z), 1e-12 * scale) << label;
      EXPECT_LE(worstRelativeExcess(lp, got.z), 1e-9) << label << describe(lp);
      checkBasis(lp, got, label);
    }
  }
  return ref.status;
}

Vec4 gaussian(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec4(n(rng), n(rng), n(rng), n(rng));
}
Vec4 unitVector(std::mt19937_64& rng) {
  return gaussian(rng).normalized();
}
double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
int uniformInt(std::mt19937_64& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
// Onto the grid of spacing 1/n, rounding to nearest or up.
Vec4 onGrid(const Vec4& v, double n) {
  return (v * n).array().round().matrix() / n;
}
double upOnGrid(double x, double n) {
  return std::ceil(x * n) / n;
}

// A polytope holding the ball of radius `radius` around `centre`: random half-spaces tangent to
// or beyond the ball; on the grid of spacing 1/16 (rows) and 1/64 (right-hand sides) if `grid`.
void addPolytopeAround(Lp& lp, std::mt19937_64& rng, const Vec4& centre, double radius, int m,
                       bool grid) {
  for (int i = 0; i < m; ++i) {
    Vec4 a = unitVector(rng) * uniform(rng, 0.5, 2.0);
    if (grid) a = onGrid(a, 16.0);
    if (a.isZero()) continue;
    const double rhs = a.dot(centre) + a.norm() * (radius + uniform(rng, 0.0, 1.0));
    lp.add(a, grid ? upOnGrid(rhs, 64.0) : rhs);
  }
}

void shuffleRows(Lp& lp, std::mt19937_64& rng) {
  std::vector<int> order(lp.rows.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::shuffle(order.begin(), order.end(), rng);
  Lp out;
  out.c = lp.c;
  for (int i : order) out.add(lp.rows[i], lp.b[i]);
  lp = out;
}

struct Tally {
  int optimal = 0, infeasible = 0, unbounded = 0;
  void count(Status s) {
    if (s == Status::kOptimal) ++optimal;
    if (s == Status::kInfeasible) ++infeasible;
    if (s == Status::kUnbounded) ++unbounded;
  }
};

TEST(SmallLpVsGlpk, RandomPolytopesWithRandomObjective) {
  // Full double data against GLPK's floating-point simplex, grid data against its exact one.
  std::mt19937_64 rng(1);
  Tally tally;
  for (int n = 0; n < 2000; ++n) {
    const bool grid = n % 2 == 1;
    Lp lp;
    const Vec4 centre = grid ? onGrid(gaussian(rng), 16.0) : gaussian(rng);
    addPolytopeAround(lp, rng, centre, uniform(rng, 0.05, 0.5), uniformInt(rng, 5, 60), grid);
    lp.c = grid ? onGrid(gaussian(rng), 16.0) : gaussian(rng);
    tally.count(checkAgainstGlpk(lp, grid, "polytope " + std::to_string(n)));
  }
  EXPECT_GT(tally.optimal, 1500);  // most random polytopes with >= 5 rows are bounded
}

TEST(SmallLpVsGlpk, InfeasibleInstances) {
  std::mt19937_64 rng(2);
  Tally tally;
  for (int n = 0; n < 1000; ++n) {
    Lp lp;
    const Vec4 centre = onGrid(gaussian(rng), 16.0);
    addPolytopeAround(lp, rng, centre, 0.2, uniformInt(rng, 4, 30), true);
    if (n % 2 == 0) {
      // Two contradictory half-spaces a.z <= beta and a.z >= beta + gap.
      const Vec4 a = onGrid(unitVector(rng), 16.0);
      const double beta = uniformInt(rng, -128, 128) / 64.0;
      lp.add(a, beta);
      lp.add(-a, -beta - uniformInt(rng, 1, 64) / 1024.0);
    } else {
      // The box |z_k - centre_k| <= 1 and a half-space beyond the box's far corner.
      for (int k = 0; k < 4; ++k) {
        lp.add(Vec4::Unit(k), centre[k] + 1.0);
        lp.add(-Vec4::Unit(k), 1.0 - centre[k]);
      }
      const Vec4 u = onGrid(unitVector(rng), 16.0);
      lp.add(u, u.dot(centre) - u.cwiseAbs().sum() - uniformInt(rng, 1, 64) / 1024.0);
    }
    lp.c = onGrid(gaussian(rng), 16.0);
    shuffleRows(lp, rng);
    tally.count(checkAgainstGlpk(lp, true, "infeasible " + std::to_string(n)));
  }
  EXPECT_EQ(tally.infeasible, 1000);
}

// An integer vector with entries in [-4, 4] and a.d <= -1 (d integer).
Vec4 recedingRow(std::mt19937_64& rng, const Vec4& d) {
  for (;;) {
    Vec4 a;
    for (int k = 0; k < 4; ++k) a[k] = uniformInt(rng, -4, 4);
    if (a.dot(d) > 0.0) a = -a;
    if (a.dot(d) < 0.0) return a;
  }
}

TEST(SmallLpVsGlpk, UnboundedInstances) {
  // Every row recedes along d (a.d < 0) and c.d < 0: the objective falls along d.
  std::mt19937_64 rng(3);
  Tally tally;
  for (int n = 0; n < 1000; ++n) {
    Lp lp;
    Vec4 d;
    for (int k = 0; k < 4; ++k) d[k] = uniformInt(rng, -3, 3);
    if (d.isZero()) d[n % 4] = 1.0;
    const Vec4 centre = onGrid(gaussian(rng), 16.0);
    const int m = uniformInt(rng, 1, 40);
    for (int i = 0; i < m; ++i) {
      const Vec4 a = recedingRow(rng, d);
      lp.add(a, a.dot(centre) + uniformInt(rng, 0, 64) / 64.0);
    }
    lp.c = recedingRow(rng, d);
    tally.count(checkAgainstGlpk(lp, true, "unbounded " + std::to_string(n)));
  }
  EXPECT_EQ(tally.unbounded, 1000);
}

TEST(SmallLpVsGlpk, RankDeficientRows) {
  // Rows that never involve z_3: unbounded if c_3 != 0, otherwise an optimal line.
  std::mt19937_64 rng(4);
  Tally tally;
  for (int n = 0; n < 500; ++n) {
    Lp lp;
    const Vec4 centre = onGrid(gaussian(rng), 16.0);
    for (int i = 0; i < uniformInt(rng, 4, 20); ++i) {
      Vec4 a = onGrid(unitVector(rng), 16.0);
      a[3] = 0.0;
      if (a.isZero()) continue;
      lp.add(a, upOnGrid(a.dot(centre) + uniform(rng, 0.1, 1.0), 64.0));
    }
    lp.c = onGrid(gaussian(rng), 16.0);
    if (n % 2 == 0) lp.c[3] = 0.0;
    tally.count(checkAgainstGlpk(lp, true, "rank deficient " + std::to_string(n)));
  }
  EXPECT_GT(tally.optimal, 100);
  EXPECT_GT(tally.unbounded, 200);
}

TEST(SmallLpVsGlpk, DegenerateVertices) {
  // Many rows through the optimal vertex v (c in the cone of their negated normals), duplicated
  // and scaled copies, parallel redundant rows and random rows with slack. Integer normals and a
  // vertex on the grid 1/16 make every b = a.v exact, so the rows truly meet at v.
  std::mt19937_64 rng(5);
  Tally tally;
  for (int n = 0; n < 2000; ++n) {
    Lp lp;
    const Vec4 v = onGrid(gaussian(rng), 16.0);
    const int through = uniformInt(rng, 4, 16);
    for (int i = 0; i < through; ++i) {
      const Vec4 a = onGrid(unitVector(rng) * uniform(rng, 1.0, 8.0), 1.0);
      if (a.isZero()) continue;
      lp.add(a, a.dot(v));
      lp.c -= (i % 3 == 2 ? 0.0 : uniformInt(rng, 0, 8) / 4.0) * a;
    }
    const int original = static_cast<int>(lp.rows.size());
    for (int i = 0; i < original; ++i) {
      switch (uniformInt(rng, 0, 3)) {
        case 0:
          lp.add(lp.rows[i], lp.b[i]);  // duplicate
          break;
        case 1:
          lp.add(3.0 * lp.rows[i], 3.0 * lp.b[i]);  // scaled duplicate
          break;
        case 2:
          lp.add(lp.rows[i], lp.b[i] + uniformInt(rng, 0, 32) / 64.0);  // parallel
          break;
        default:
          break;
      }
    }
    addPolytopeAround(lp, rng, v, 0.3, uniformInt(rng, 0, 10), true);
    shuffleRows(lp, rng);
    const Status s = checkAgainstGlpk(lp, true, "degenerate " + std::to_string(n));
    tally.count(s);
    if (s == Status::kOptimal) {
      const SmallLpResult got = lp.solve();
      EXPECT_NEAR(got.objective, lp.c.dot(v), 1e-9 * lp.c.norm() * problemSize(lp, v));
    }
  }
  EXPECT_GT(tally.optimal, 1800);
}

TEST(SmallLpVsGlpk, SmallIntegerInstances) {
  // Coefficients in {-2..2} and right-hand sides in {-1..3}: exact ties everywhere, many rows
  // through each vertex, parallel and duplicated rows, and all three outcomes.
  std::mt19937_64 rng(6);
  Tally tally;
  for (int n = 0; n < 3000; ++n) {
    Lp lp;
    const int m = uniformInt(rng, 1, 24);
    for (int i = 0; i < m; ++i) {
      Vec4 a;
      for (int k = 0; k < 4; ++k) a[k] = uniformInt(rng, -2, 2);
      lp.add(a, uniformInt(rng, n % 3 == 0 ? -1 : 0, 3));
    }
    if (n % 2 == 0) {
      for (int k = 0; k < 4; ++k) {
        lp.add(Vec4::Unit(k), 1.0);
        lp.add(-Vec4::Unit(k), 1.0);
      }
    }
    for (int k = 0; k < 4; ++k) lp.c[k] = uniformInt(rng, -2, 2);
    tally.count(checkAgainstGlpk(lp, true, "integer " + std::to_string(n)));
  }
  EXPECT_GT(tally.optimal, 300);
  EXPECT_GT(tally.infeasible, 300);
  EXPECT_GT(tally.unbounded, 300);
}

TEST(SmallLp, HypercubeCornerWithManyActiveRows) {
  // Minimise -(z0+z1+z2+z3) over [-1,1]^4 cut by rows through the corner (1,1,1,1): 10 rows are
  // active at the optimum, which is the corner with objective -4.
  Lp lp;
  for (int k = 0; k < 4; ++k) {
    lp.add(Vec4::Unit(k), 1.0);
    lp.add(-Vec4::Unit(k), 1.0);
  }
  lp.add(Vec4(1, 1, 0, 0), 2.0);
  lp.add(Vec4(0, 1, 1, 0), 2.0);
  lp.add(Vec4(1, 1, 1, 1), 4.0);
  lp.add(Vec4(1, 1, 1, 1), 4.0);
  lp.add(Vec4(2, 0, 0, 2), 4.0);
  lp.add(Vec4(1, 0, 1, 1), 3.0);
  lp.c = -Vec4::Ones();
  const SmallLpResult r = lp.solve();
  ASSERT_EQ(r.status, Status::kOptimal);
  EXPECT_NEAR(r.objective, -4.0, 1e-14);
  EXPECT_LE((r.z - Vec4::Ones()).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(SmallLp, EdgeCases) {
  const Vec4 c(0.5, -1.0, 0.0, 2.0);
  std::vector<Vec4> none;
  std::vector<double> no_b;
  EXPECT_EQ(solveSmallLp(none, no_b, c).status, Status::kUnbounded);
  const SmallLpResult zero_c = solveSmallLp(none, no_b, Vec4::Zero());
  EXPECT_EQ(zero_c.status, Status::kOptimal);
  EXPECT_EQ(zero_c.objective, 0.0);

  // A zero row is 0 <= b: infeasible for b < 0, ignored for b >= 0.
  Lp lp;
  lp.add(Vec4::Zero(), -1e-300);
  EXPECT_EQ(lp.solve().status, Status::kInfeasible);
  lp.b[0] = 0.0;
  lp.add(Vec4(1, 0, 0, 0), 1.0);
  lp.add(Vec4(-1, 0, 0, 0), 1.0);
  lp.c = Vec4(1, 0, 0, 0);
  // The slab |z0| <= 1: optimal, although the optimal set is a 3-dimensional plane.
  const SmallLpResult slab = lp.solve();
  ASSERT_EQ(slab.status, Status::kOptimal);
  EXPECT_EQ(slab.objective, -1.0);
  EXPECT_EQ(slab.z[0], -1.0);

  std::vector<double> short_b{1.0};
  EXPECT_THROW(solveSmallLp(lp.rows, short_b, lp.c), Error);
  lp.rows[1][2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(lp.solve(), GeometryError);
  lp.rows[1][2] = 0.0;
  lp.c[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(lp.solve(), GeometryError);
}

TEST(SmallLp, DeterministicAndAllocationFreeOnceWarm) {
  // Up to 64 rows nothing is allocated; above, a per-thread buffer grows on the first solve of
  // that size and is reused after.
  std::mt19937_64 rng(7);
  for (int m : {12, 64, 65, 200}) {
    Lp lp;
    addPolytopeAround(lp, rng, gaussian(rng), 0.3, m, false);
    lp.c = gaussian(rng);
    long before = polydem::testing::allocationCount();
    const SmallLpResult first = lp.solve();
    if (m <= 64) {
      EXPECT_EQ(polydem::testing::allocationCount(), before) << m << " rows";
    }
    before = polydem::testing::allocationCount();
    const SmallLpResult second = lp.solve();
    EXPECT_EQ(polydem::testing::allocationCount(), before) << m << " rows";
    const SmallLpResult warm = solveSmallLp(lp.rows, lp.b, lp.c, first.basis);
    EXPECT_EQ(polydem::testing::allocationCount(), before) << m << " rows";
    EXPECT_EQ(warm.iterations, 0);
    EXPECT_EQ(first.status, Status::kOptimal) << m << " rows";
    EXPECT_EQ(first.status, second.status);
    EXPECT_EQ(first.iterations, second.iterations);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(first.z[k], second.z[k]);
  }
}

TEST(SmallLp, SameAnswerInMillimetresAndKilometres) {
  // Lengths scaled by 1e-3 or 1e3 (b and hence z; the normals are dimensionless): the same
  // pivots, and the optimum scaled by the same factor.
  std::mt19937_64 rng(8);
  for (int n = 0; n < 500; ++n) {
    Lp lp;
    addPolytopeAround(lp, rng, gaussian(rng), 0.2, uniformInt(rng, 5, 40), false);
    lp.c = gaussian(rng);
    const SmallLpResult base = lp.solve();
    for (double scale : {1e-3, 1e3}) {
      Lp scaled = lp;
      for (double& rhs : scaled.b) rhs *= scale;
      const SmallLpResult got = scaled.solve();
      ASSERT_EQ(got.status, base.status) << n;
      EXPECT_EQ(got.iterations, base.iterations) << n;
      if (base.status != Status::kOptimal) continue;
      EXPECT_NEAR(got.objective, scale * base.objective, 1e-12 * scale * std::abs(base.objective));
      EXPECT_LE((got.z - scale * base.z).norm(), 1e-12 * scale * base.z.norm()) << n;
    }
  }
}

// The six faces of the cube of edge `edge` centred at `centre`, as rows (n, extra) with
// right-hand side n.centre + edge / 2.
void addCubeFaces(Lp& lp, const Eigen::Vector3d& centre, double edge, double extra) {
  for (int k = 0; k < 3; ++k) {
    for (double sign : {1.0, -1.0}) {
      Vec4 a = Vec4::Zero();
      a[k] = sign;
      a[3] = extra;
      lp.add(a, sign * centre[k] + 0.5 * edge);
    }
  }
}

TEST(SmallLp, ChebyshevCentreOfCube) {
  // Maximise r s.t. n_i.x + r <= d_i: the cube [-a,a]^3 around q has r = a at x = q; six rows
  // are active at the optimum (a degenerate vertex in R^4).
  for (double a : {1e-3, 1.0, 1e3}) {
    const Eigen::Vector3d q(0.3 * a, -2.0 * a, 0.7 * a);
    Lp lp;
    addCubeFaces(lp, q, 2.0 * a, 1.0);
    lp.c = Vec4(0, 0, 0, -1);
    const SmallLpResult r = lp.solve();
    ASSERT_EQ(r.status, Status::kOptimal) << a;
    EXPECT_NEAR(r.z[3], a, 1e-14 * a);
    EXPECT_NEAR(-r.objective, a, 1e-14 * a);
    EXPECT_LE((r.z.head<3>() - q).norm(), 1e-14 * a);
  }
}

// Boon et al. (2012) overlap test for axis-aligned unit cubes A (centred at 0) and B (centred at
// delta), scaled by L: minimise s s.t. n_i.x - s <= d_i over the 12 faces. Per axis k the rows
// ask |x_k| <= L/2 + s and |x_k - L delta_k| <= L/2 + s; two intervals of half-width w centred
// 0 and L delta_k meet iff 2w >= L |delta_k|, so
//   s* = L (max_k |delta_k| - 1) / 2,
// i.e. minus half the smallest overlap depth (L - L|delta_k|) when the cubes overlap, and half
// the largest gap along an axis when they are apart. The optimal x_k is unique only on the axis
// of the maximum: x_k = L delta_k / 2.
void checkCubePair(const Eigen::Vector3d& delta, double scale) {
  Lp lp;
  addCubeFaces(lp, Eigen::Vector3d::Zero(), scale, -1.0);
  addCubeFaces(lp, scale * delta, scale, -1.0);
  lp.c = Vec4(0, 0, 0, 1);
  const SmallLpResult r = lp.solve();
  ASSERT_EQ(r.status, Status::kOptimal);
  const double expected = scale * (delta.cwiseAbs().maxCoeff() - 1.0) / 2.0;
  EXPECT_NEAR(r.objective, expected, 1e-14 * scale);
  EXPECT_NEAR(r.z[3], expected, 1e-14 * scale);
  int axis = 0;
  delta.cwiseAbs().maxCoeff(&axis);
  EXPECT_NEAR(r.z[axis], scale * delta[axis] / 2.0, 1e-14 * scale);
  EXPECT_LE(worstRelativeExcess(lp, r.z), 1e-14);
}

TEST(SmallLp, PotentialBlockOverlapOfTwoCubes) {
  for (double scale : {1e-3, 1.0, 1e3}) {
    checkCubePair(Eigen::Vector3d(0.3, 0.2, 0.1), scale);   // overlap: s* = -0.35 scale
    checkCubePair(Eigen::Vector3d(1.4, 0.2, 0.1), scale);   // apart:   s* = +0.2 scale
    checkCubePair(Eigen::Vector3d(-0.1, 0.0, 1.0), scale);  // touching faces: s* = 0
    checkCubePair(Eigen::Vector3d(1.0, 1.0, 1.0), scale);   // touching corners: s* = 0
  }
}

// Boon et al.'s overlap LP for the faces of two placed polyhedra: minimise s s.t.
// a_i . x - s <= d_i, with A at the origin and B moved by (R, t).
Lp contactLp(const ConvexPolyhedron& a, const ConvexPolyhedron& b, const Mat3& r, const Vec3& t) {
  Lp lp;
  for (const Face& f : a.faces())
    lp.add(Vec4(f.normal.x(), f.normal.y(), f.normal.z(), -1.0), f.offset);
  for (const Face& f : b.faces()) {
    const Vec3 n = r * f.normal;
    lp.add(Vec4(n.x(), n.y(), n.z(), -1.0), f.offset + n.dot(t));
  }
  lp.c = Vec4(0, 0, 0, 1);
  return lp;
}

Mat3 randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// Random convex polyhedra with 8-40 vertices; `thin` ones are plates (one semi-axis 1e-3..1e-2 of
// the others) or rods (two).
ConvexPolyhedron randomPolyhedron(std::mt19937_64& rng, std::uint64_t seed, bool thin = false) {
  Vec3 axes(uniform(rng, 0.3, 1.0), uniform(rng, 0.3, 1.0), uniform(rng, 0.3, 1.0));
  if (thin) {
    axes[seed % 3] *= uniform(rng, 1e-3, 1e-2);
    if (seed % 2 == 0) axes[(seed + 1) % 3] *= uniform(rng, 1e-3, 1e-2);
  }
  return ConvexPolyhedron::fromPoints(
      shapes::randomConvex(uniformInt(rng, 8, 40), seed, axes, 0.2));
}

TEST(SmallLpVsGlpk, ContactShapedInstances) {
  // Two random polyhedra (8-40 vertices; a quarter of them plates or rods 1e-3..1e-2 thin) at
  // distances from deep overlap to well apart, and axis-aligned boxes in face contact (many rows
  // through the optimum, optimal faces).
  std::mt19937_64 rng(9);
  int overlapping = 0, apart = 0;
  for (int n = 0; n < 800; ++n) {
    const ConvexPolyhedron a = randomPolyhedron(rng, 1000 + n, n % 4 == 1);
    const ConvexPolyhedron b = randomPolyhedron(rng, 5000 + n, n % 4 == 2);
    const Vec3 t = unitVector(rng).head<3>().normalized() * uniform(rng, 0.0, 2.5);
    const Lp lp = contactLp(a, b, randomRotation(rng), t);
    ASSERT_EQ(checkAgainstGlpk(lp, false, "contact " + std::to_string(n)), Status::kOptimal);
    (lp.solve().objective < 0.0 ? overlapping : apart) += 1;
  }
  EXPECT_GT(overlapping, 150);
  EXPECT_GT(apart, 150);
  const ConvexPolyhedron cube = ConvexPolyhedron::fromPoints(shapes::cube(1.0));
  for (int n = 0; n < 200; ++n) {
    // Face on face with a lateral offset, depth from 0.2 to -0.2 (apart), on the grid 1/64.
    const Vec3 t(uniformInt(rng, -48, 48) / 64.0, uniformInt(rng, -48, 48) / 64.0,
                 1.0 - uniformInt(rng, -13, 13) / 64.0);
    EXPECT_EQ(checkAgainstGlpk(contactLp(cube, cube, Mat3::Identity(), t), true,
                               "face-face " + std::to_string(n)),
              Status::kOptimal);
  }
}

TEST(SmallLp, WarmStartFromANearbyBasis) {
  // The optimal basis of a pair, offered to the same pair moved a little (a time step): the
  // same answer as a cold solve, in fewer pivots on average; from its own basis, no pivot.
  std::mt19937_64 rng(10);
  long cold_pivots = 0, warm_pivots = 0;
  for (int n = 0; n < 400; ++n) {
    const ConvexPolyhedron a = randomPolyhedron(rng, 9000 + n);
    const ConvexPolyhedron b = randomPolyhedron(rng, 9500 + n);
    const Mat3 r = randomRotation(rng);
    const Vec3 t = unitVector(rng).head<3>().normalized() * uniform(rng, 0.2, 2.0);
    const Lp before = contactLp(a, b, r, t);
    const SmallLpResult first = before.solve();
    ASSERT_EQ(first.status, Status::kOptimal);
    const SmallLpResult again = solveSmallLp(before.rows, before.b, before.c, first.basis);
    EXPECT_EQ(again.iterations, 0) << n;
    EXPECT_NEAR(again.objective, first.objective, 1e-12 * problemSize(before, first.z)) << n;

    const Mat3 turn = Eigen::AngleAxisd(1e-3, unitVector(rng).head<3>().normalized()).matrix();
    const Lp after = contactLp(a, b, turn * r, t + 1e-3 * unitVector(rng).head<3>());
    const Reference ref = solveWithGlpk(after, false);
    ASSERT_EQ(ref.status, Status::kOptimal);
    for (const SmallLpOptions& options : kOptionSets) {
      const SmallLpResult warm = solveSmallLp(after.rows, after.b, after.c, first.basis, options);
      ASSERT_EQ(warm.status, Status::kOptimal) << n;
      EXPECT_NEAR(warm.objective, ref.objective, 1e-9 * problemSize(after, ref.z)) << n;
      EXPECT_LE(worstRelativeExcess(after, warm.z), 1e-9) << n;
      checkBasis(after, warm, "warm " + std::to_string(n));
    }
    cold_pivots += after.solve().iterations;
    warm_pivots += solveSmallLp(after.rows, after.b, after.c, first.basis).iterations;
  }
  EXPECT_LT(warm_pivots * 4, cold_pivots);
}

TEST(SmallLp, UnusableWarmBasesFallBackToColdStarts) {
  std::mt19937_64 rng(11);
  for (int n = 0; n < 300; ++n) {
    Lp lp;
    addPolytopeAround(lp, rng, gaussian(rng), 0.3, uniformInt(rng, 6, 30), false);
    lp.add(Vec4::Zero(), 1.0);  // a zero row: index m-1, never usable in a basis
    lp.c = gaussian(rng);
    const int m = static_cast<int>(lp.rows.size());
    const SmallLpResult cold = lp.solve();
    std::array<int, 4> basis{};
    switch (n % 5) {
      case 0:  // out of range
        basis = {0, 1, 2, m};
        break;
      case 1:  // an artificial row
        basis = {-1, 0, 1, 2};
        break;
      case 2:  // a repeated row
        basis = {0, 1, 1, 2};
        break;
      case 3:  // the zero row
        basis = {0, 1, 2, m - 1};
        break;
      default:  // random rows: mostly not dual feasible
        for (int& j : basis) j = uniformInt(rng, 0, m - 2);
        break;
    }
    const SmallLpResult warm = solveSmallLp(lp.rows, lp.b, lp.c, basis);
    ASSERT_EQ(warm.status, cold.status) << n;
    if (cold.status != Status::kOptimal) continue;
    EXPECT_NEAR(warm.objective, cold.objective, 1e-9 * lp.c.norm() * problemSize(lp, cold.z));
    checkBasis(lp, warm, "fallback " + std::to_string(n));
  }
  // Two rows that are the same plane (a singular basis) must not be taken.
  Lp box;
  for (int k = 0; k < 4; ++k) {
    box.add(Vec4::Unit(k), 1.0);
    box.add(-Vec4::Unit(k), 1.0);
  }
  box.add(2.0 * Vec4::Unit(0), 2.0);  // row 8 = row 0 scaled
  box.c = -Vec4::Ones();
  const SmallLpResult r = solveSmallLp(box.rows, box.b, box.c, {0, 8, 2, 4});
  ASSERT_EQ(r.status, Status::kOptimal);
  EXPECT_NEAR(r.objective, -4.0, 1e-14);
}

TEST(SmallLp, ZeroRowsKeepTheCallersIndices) {
  // Basis indices refer to the caller's rows even when zero rows come first.
  Lp lp;
  lp.add(Vec4::Zero(), 0.0);
  lp.add(Vec4::Zero(), 3.0);
  for (int k = 0; k < 4; ++k) {
    lp.add(Vec4::Unit(k), 1.0);
    lp.add(-Vec4::Unit(k), 1.0);
  }
  lp.c = Vec4(1, 2, -3, 4);
  const SmallLpResult r = lp.solve();
  ASSERT_EQ(r.status, Status::kOptimal);
  std::array<int, 4> sorted = r.basis;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::array<int, 4>{3, 5, 6, 9}));  // -z0, -z1, +z2, -z3 at the optimum
  checkBasis(lp, r, "zero rows");
}

}  // namespace
}  // namespace polydem::geometry
