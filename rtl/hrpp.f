rtl/hrpp_pkg.sv
rtl/hrpp_ram_1r1w.sv
rtl/hrpp_fifo.sv
rtl/hrpp_hash.sv
rtl/hrpp_pred_table.sv
rtl/hrpp_skip_ctrl.sv
rtl/hrpp_lanes.sv
rtl/hrpp_top.sv
