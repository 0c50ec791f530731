// The crex: a regular expression over light-transport components (spec/crex.md §2).
//
// The grammar is deliberately permissive. Stray repeats, stray or mismatched closers, unknown
// letters and unknown characters all parse into the tree, so that the AST builder reports them
// in crex's own words (E001, E002, E008) with precise spans and keeps going: every error of an
// expression is reported in one pass, and ANTLR's generic recovery messages are never shown.
// Which letters are components is decided by the component table (base/components.h),
// not here, so a new component is one row of that table.
//
// It is shaped for linear-time parsing: a repeat can only be stray at the start of a sequence
// (anywhere else it binds to the atom before it), and the one remaining ambiguity, the closer
// that may be missing at the end of input, is resolved greedily by SLL prediction (parse.cpp).
grammar Crex;

crex        : sequence (strayClose sequence)* EOF ;
sequence    : strayRepeat* item* ;
item        : atom repeat* ;
atom        : LETTER                            # letter
            | OPEN sequence CLOSE?              # group
            | BAD_CHAR                          # badChar
            ;
repeat      : STAR | INTEGER ;
strayRepeat : repeat ;
strayClose  : CLOSE ;

OPEN        : [(<{[] ;
CLOSE       : [)>}\]] ;
LETTER      : [A-Za-z] ;
STAR        : '*' ;
INTEGER     : [0-9]+ ;
WS          : [ \t\r\n\f\u000B]+ -> skip ;
BAD_CHAR    : . ;
