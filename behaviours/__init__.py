"""The mission behaviours: the state machine between perception and the servo/link.

Modules (nouns, py_trees-like): ``machine`` (the one table of states and triggers, the Mission
model), ``states`` (each state's enter / tick / exit), ``blackboard`` (the shared context and the
``behaviour.*`` settings), ``evidence`` (raised arm, steady pointing, votes), ``tracker`` (keeps
the chosen object identified), ``acknowledge`` (nod / lights), ``loop`` (the controller tick,
frame processing, the perception worker of ``run``).
"""
