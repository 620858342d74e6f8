//! A timing-accurate model of the SERCON816 controller and its SERCON410B-compatible
//! variant: registers, dual-port RAM, interrupts, timers, telegram processing.
