#!/usr/bin/env python3
# Drafts the schemas of the detector commands (tunnel, simulate,
# calibrate-threshold) from sample outputs:
#   python3 docs/schemas/draft_schema.py NAME TITLE out1.json,out2.json NULLABLE_KEYS
# The committed schemas are these drafts with descriptions added by hand.
import json,sys
# Draft a JSON Schema from sample outputs: types inferred, every key required,
# numbers nullable where any sample or the `nullable` list has null.
nullable=set(sys.argv[4].split(',')) if len(sys.argv)>4 else set()
def merge(samples, key=None):
    vals=[s for s in samples]
    types=set()
    for v in vals:
        types.add({dict:'object',list:'array',str:'string',bool:'boolean',int:'integer',float:'number',type(None):'null'}[type(v)])
    if 'integer' in types and 'number' in types: types.discard('integer')
    if key in nullable: types.add('null')
    sch={}
    nonnull=[v for v in vals if v is not None]
    if 'object' in types:
        objs=[v for v in nonnull if isinstance(v,dict)]
        keys=[]
        for o in objs:
            for k in o:
                if k not in keys: keys.append(k)
        sch['properties']={k:merge([o[k] for o in objs if k in o],k) for k in keys}
        sch['required']=[k for k in keys if all(k in o for o in objs)]
    if 'array' in types:
        items=[x for v in nonnull if isinstance(v,list) for x in v]
        if items: sch['items']=merge(items,key)
    if 'integer' in types and len(types - {'null'})==1 and key not in ('seeds','seed'):
        pass
    t=sorted(types)
    sch={'type': t[0] if len(t)==1 else t, **sch}
    if sch['type']=='integer' or sch['type']==['integer','null']:
        sch['minimum']=0
    return sch
samples=[json.load(open(f)) for f in sys.argv[3].split(',')]
s=merge(samples)
s={'$schema':'https://json-schema.org/draft/2020-12/schema','$id':f'https://extrinsic-audit.invalid/schemas/{sys.argv[1]}.schema.json','title':sys.argv[2],**s}
s['properties']['schema_version']={'const':1,'description':'Version of this schema; fields are only added within a version.'}
s['properties']['warnings']={'type':'array','items':{'type':'string'},'description':'Warnings, one line each (also printed on stderr).'}
s['additionalProperties']=True
print(json.dumps(s,indent=2))
