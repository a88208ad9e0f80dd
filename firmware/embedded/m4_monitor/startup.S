/* Start-up of the Cortex-M4 monitor image on QEMU's mps2-an386 (the replay image's linker script, mps2_an386.ld),
   the replay image's start-up with its own entry points: the vector table at
   address 0 (the M-profile reset reads the initial SP and PC from it), then Reset_Handler: FPU access on (the code is
   built with -mfloat-abi=hard, and any FP instruction before CPACR grants access faults), .data copied from its load
   address, .bss zeroed, and m4_monitor_start() (monitor_main.cpp: constructors, the monitor, semihosting exit).
   Every exception other than reset and SysTick ends in m4_monitor_fault() with its number (IPSR), which reports it and
   exits. SysTick and the Ethernet interrupt only wake the main loop's WFI (PRIMASK is set: they are never taken; a
   handler that returns is there all the same). */
  .syntax unified
  .cpu cortex-m4
  .fpu fpv4-sp-d16
  .thumb

  .section .isr_vector, "a", %progbits
  .align 2
  .global m4_vectors
m4_vectors:
  .word _estack
  .word Reset_Handler
  .rept 13                  /* NMI, HardFault, MemManage, BusFault, UsageFault, 4 reserved, SVC, DebugMon, 1 reserved,
                               PendSV */
  .word Fault_Handler
  .endr
  .word Wake_Handler        /* SysTick: wakes WFI */
  .rept 13                  /* external interrupts 0-12: none are enabled */
  .word Fault_Handler
  .endr
  .word Wake_Handler        /* IRQ 13: the LAN9118 */
  .rept 18
  .word Fault_Handler
  .endr

  .text
  .align 2
  .thumb_func
  .global Reset_Handler
  .type Reset_Handler, %function
Reset_Handler:
  ldr r0, =0xE000ED88       /* SCB->CPACR: CP10 and CP11 full access */
  ldr r1, [r0]
  orr r1, r1, #(0xF << 20)
  str r1, [r0]
  dsb
  isb
  ldr r0, =_sdata           /* .data from its load address */
  ldr r1, =_edata
  ldr r2, =_sidata
1:
  cmp r0, r1
  bhs 2f
  ldr r3, [r2], #4
  str r3, [r0], #4
  b 1b
2:
  ldr r0, =_sbss            /* .bss = 0 */
  ldr r1, =_ebss
  movs r3, #0
3:
  cmp r0, r1
  bhs 4f
  str r3, [r0], #4
  b 3b
4:
  bl m4_monitor_start        /* does not return */
5:
  b 5b
  .size Reset_Handler, . - Reset_Handler

  .thumb_func
  .global Wake_Handler
  .type Wake_Handler, %function
Wake_Handler:
  bx lr
  .size Wake_Handler, . - Wake_Handler

  .thumb_func
  .global Fault_Handler
  .type Fault_Handler, %function
Fault_Handler:
  mrs r0, ipsr
  bl m4_monitor_fault        /* does not return */
6:
  b 6b
  .size Fault_Handler, . - Fault_Handler
