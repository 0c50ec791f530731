// The pipeline language (spec/pipeline.md; docs/pipeline-language.md). A file holds pipelines;
// a pipeline is a block of statements: sections (`preselective { ... }`), definitions
// (`sal = saliency(preview)`), selective variables (`vary spp 1 .. 25 by imp`, one component's:
// `vary subsample(D) 8 .. 1 by dd refine 0.5`) and settings
// (`image 512 x 512`, `budget 10 s`, `crex "TT" by imp`). Which sections, settings, operators
// and variables exist is not decided here but by the checker's tables, so messages can name
// what was expected and suggest the nearest name. Crex literals are parsed again by the crex
// parser at their file offset.
grammar Pipeline;

@parser::members {
  // Units and the `x` of `image 512 x 512` are ordinary identifiers everywhere else (a map may
  // be called `s` or `x`): an identifier is that word here only when what follows it does not
  // start a statement of its own (`s = ...`, `x(...)`, `deg { ... }`).
  bool wordHere(std::initializer_list<const char*> words) {
    antlr4::Token* t = _input->LT(1);
    if (t->getType() != IDENT) return false;
    size_t next = _input->LA(2);
    if (next == ASSIGN || next == LPAREN || next == LBRACE) return false;
    for (const char* w : words)
      if (t->getText() == w) return true;
    return false;
  }
}

file        : pipeline* EOF ;
pipeline    : PIPELINE name=IDENT (EXTENDS base=IDENT)? block ;
block       : LBRACE statement* RBRACE ;
statement   : IDENT block                                            # section
            | IDENT ASSIGN expr                                      # definition
            | VARY name=IDENT (LPAREN comp=IDENT RPAREN)? lo=value RANGE hi=value BY expr (USING fn=IDENT)?
              ({wordHere({"refine"})}? refineWord=IDENT refine=value)?   # vary
            | IDENT value* (BY expr)?                                # setting
            ;
expr        : IDENT LPAREN (arg (COMMA arg)*)? RPAREN                # call
            | IDENT                                                  # reference
            | value                                                  # literal
            ;
arg         : IDENT value                                            # namedArg
            | expr                                                   # positionalArg
            ;
value       : NUMBER unit? | STRING | TRUE | FALSE | {wordHere({"x"})}? IDENT ;
unit        : PERCENT | {wordHere({"s", "ms", "deg"})}? IDENT ;

PIPELINE    : 'pipeline' ;
EXTENDS     : 'extends' ;
VARY        : 'vary' ;
BY          : 'by' ;
USING       : 'using' ;
TRUE        : 'true' ;
FALSE       : 'false' ;
PERCENT     : '%' ;
RANGE       : '..' ;
LBRACE      : '{' ;
RBRACE      : '}' ;
LPAREN      : '(' ;
RPAREN      : ')' ;
COMMA       : ',' ;
ASSIGN      : '=' ;
NUMBER      : '-'? [0-9]+ ('.' [0-9]+)? ([eE] [+-]? [0-9]+)? | '-'? '.' [0-9]+ ;
STRING      : '"' ~["\r\n]* '"' ;
IDENT       : [A-Za-z_] [A-Za-z_0-9]* ;
LINE_COMMENT: '//' ~[\r\n]* -> skip ;
BLOCK_COMMENT: '/*' .*? '*/' -> skip ;
WS          : [ \t\r\n\f]+ -> skip ;
BAD_CHAR    : . ;
