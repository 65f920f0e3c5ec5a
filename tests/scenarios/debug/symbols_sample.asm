; A tiny ROM whose nasm map the symbol-table tests read (symbols_test.cpp). The layout is chosen so
; that each address can be worked out by hand: org 0, `entry` at image offset 0, a 3-byte
; instruction before `helper` (offset 3), 4 bytes of code before `table` (offset 7), 5 data
; bytes; `.bss` is nobits at linear 0x400 with `counter` (2 bytes) then `flags`. The constants
; (`equ`, a struc's offsets, `absolute` labels) are listed in the map's "No Section" part.
[map all symbols_sample.map]
BAUD    equ 9600
MINUS   equ -1
struc frame
  .ip:  resw 1
  .cs:  resw 1
endstruc
        org 0
section .text
entry:  mov ax, 0x1234          ; B8 34 12: 3 bytes
helper: inc ax                  ; 40
        inc ax                  ; 40
        ret                     ; C3
        nop                     ; 90: helper is 4 bytes
table:  db 1, 2, 3, 4, 5
section .bss nobits vstart=0x400
counter: resw 1
flags:   resb 1
absolute 0x500
scratch: resb 4
