#pragma once
// Private to kc::core: how the system's BLAS runs inside kcwarp's own parallelism.

namespace kc::detail {

/// Sets a threaded OpenBLAS to one thread when it has more (nothing for another BLAS). kcwarp's
/// parallel loops are its own (parallelFor); the BLAS is called from CHOLMOD's supernodal
/// factorization and the rigidity QP's dense factorizations between them. A threaded OpenBLAS
/// leaves its idle workers spinning (sched_yield) for a while after every call, and on a machine
/// with few cores they take the cores parallelFor's threads need. Called at every entry point
/// that reaches the BLAS (sparse_cholesky.h, dense_blas.h).
void serialBlas();

}  // namespace kc::detail
