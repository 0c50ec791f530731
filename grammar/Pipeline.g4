// The pipeline language (spec/pipeline.md; docs/pipeline-language.md). A file holds pipelines;
// a pipeline is a block of statements: sections (`preselective { ... }`), definitions
// (`sal = saliency(preview)`), selective variables (`vary spp 1 .. 25 by imp`) and settings
// (`image 512 x 512`, `budget 10 s`, `crex "TT" by imp`). Which sections, settings, operators
// and variables exist is not decided here but by the checker's tables, so messages can name
// what was expected and suggest the nearest name. Crex literals are parsed again by the crex
// parser at their file offset.
grammar Pipeline;

file        : pipeline* EOF ;
pipeline    : PIPELINE name=IDENT (EXTENDS base=IDENT)? block ;
block       : LBRACE statement* RBRACE ;
statement   : IDENT block                                            # section
            | IDENT ASSIGN expr                                      # definition
            | VARY IDENT lo=value RANGE hi=value BY expr (USING IDENT)?   # vary
            | IDENT value* (BY expr)?                                # setting
            ;
expr        : IDENT LPAREN (arg (COMMA arg)*)? RPAREN                # call
            | IDENT                                                  # reference
            | value                                                  # literal
            ;
arg         : IDENT value                                            # namedArg
            | expr                                                   # positionalArg
            ;
value       : NUMBER unit? | STRING | TRUE | FALSE | X ;
unit        : S | MS | PERCENT | DEG ;

PIPELINE    : 'pipeline' ;
EXTENDS     : 'extends' ;
VARY        : 'vary' ;
BY          : 'by' ;
USING       : 'using' ;
TRUE        : 'true' ;
FALSE       : 'false' ;
X           : 'x' ;
S           : 's' ;
MS          : 'ms' ;
DEG         : 'deg' ;
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
