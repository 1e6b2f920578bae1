#pragma once
// The CPU time this process has used (every thread), in seconds: what learning and `reproduce` report beside
// wall time, since a shared machine's wall time says little (CLOCK_PROCESS_CPUTIME_ID).

namespace uascma {

double ProcessCpuSeconds();

}  // namespace uascma
