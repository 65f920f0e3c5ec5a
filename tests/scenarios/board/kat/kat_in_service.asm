; (2) A higher-priority handler in service: IR1 wakes main; its handler writes OCW3 (no EOI),
; enables interrupts and halts with IR1 in service. IR3 (lower) rises: the 8259A holds it. IR0
; (higher) wakes IR1's handler and runs (H); IR1's handler ends with (H): its EOI lets IR3 in.
[map all kat_in_service.map]
%include "latency_kat.inc"
        INIT 0xF4               ; IR0, IR1, IR3
        sti
        hlt
        nop
        jmp main + 1
        ISR 0
        AT 0x240
isr1:   mov al, 0x0B            ; OCW3: read ISR (an OUT to 0C0h that is no EOI)
        out 0xC0, al
        sti
        hlt                     ; F000:0245: IR0 returns to F000:0246 (even)
isr1_eoi:
        EOI_IRET                ; MOV AL,20h at 0246, OUT 0C0h,AL at 0248
        ISRS 2, 7
        RESET
