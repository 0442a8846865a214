#pragma once
// How much memory this process may use: the least of the machine's RAM, the cgroup's limit
// (containers, CI) and the address-space limit (ulimit -v).
namespace fnopt {

double usable_memory_bytes();

}  // namespace fnopt
