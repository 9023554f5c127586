#pragma once
// Private to src/linalg/trilinos: the Tpetra types of the Trilinos backends, and what the
// replicated (trilinos_solver.cpp) and the distributed (distributed_solver.cpp) solvers share:
// MueLu's parameters and the Belos solve that accepts on the true residual.
#include "talus/linalg/linear_solver.hpp"

#include <Teuchos_ParameterList.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Map.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Operator.hpp>

#include <string>

namespace talus::detail {

using SC = double;
using map_type = Tpetra::Map<>;
using LO = map_type::local_ordinal_type;
using GO = map_type::global_ordinal_type;
using NO = map_type::node_type;
using matrix_type = Tpetra::CrsMatrix<SC, LO, GO, NO>;
using MV = Tpetra::MultiVector<SC, LO, GO, NO>;
using OP = Tpetra::Operator<SC, LO, GO, NO>;

/// Smoothed aggregation for an elasticity-like operator of `rows` rows spread over `ranks`
/// processes. On several, the coarse levels are repartitioned onto fewer ranks by the rows'
/// coordinates, which the caller must add to the "user data" sublist as "Coordinates".
Teuchos::ParameterList muelu_parameters(int ranks, long long rows);

/// Solves A X = B (X holds the initial guess) with Belos CG (`cg`) or GMRES, the
/// preconditioner on the left for CG and on the right for GMRES (so GMRES's residual stays the
/// true one). Accepts on the true relative residual ||B - A X|| / ||B||: if the solver's own
/// measure (recursive, preconditioned) stopped short of it, up to two restarts from the iterate
/// ask for the missing factor, and a solve that stagnates within 100x the tolerance is
/// accepted (round-off). Throws NumericalError (naming `description`) otherwise. B must not be
/// zero.
LinearSolveStats belos_solve(bool cg, const Teuchos::RCP<const OP>& A, const Teuchos::RCP<OP>& prec,
                             const Teuchos::RCP<MV>& X, const Teuchos::RCP<const MV>& B,
                             double tolerance, int max_iterations, const std::string& description);

} // namespace talus::detail
