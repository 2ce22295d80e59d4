#pragma once
// Cooperative handling of SIGINT/SIGTERM: long loops poll interrupt_requested().
namespace granflow {

void install_interrupt_handlers();
bool interrupt_requested();
// Throws Interrupted if a signal arrived; call at safe points of long loops.
void check_interrupt();

}  // namespace granflow
